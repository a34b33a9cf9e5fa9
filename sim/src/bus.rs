//! The simulated CAN bus of the P-Rob2: six [`SimDrive`]s, the arm model, the emergency switch
//! and the fault injections, behind [`mcm_bus::Bus`] and [`crate::SimControl`].
//!
//! Runs inside the cycle: `send` and `recv` never block and never allocate (the receive queue
//! is a fixed ring of [`RX_CAPACITY`] frames; when it is full, new frames are dropped and
//! counted, like a CAN controller's receive overrun).
//!
//! Lock-step time (`docs/drive-profile.md`, "The simulated drive"): time advances only on SYNC
//! (`080#`), by exactly one cycle period (or on [`SimBus::period_without_sync`], a fault
//! injection: the period passes but the SYNC never reaches the drives, so they neither apply
//! RPDOs nor send TPDOs). On SYNC every drive applies its latched RPDOs and sends
//! its TPDOs (sampled at the SYNC), then the physics runs the period in sub-steps of
//! `sim.physics_step_us`; in each sub-step every drive computes its motor current from the true
//! joint state, the joint torques (current x `torque_per_amp`) go to [`ArmSim::step`], and the
//! holding brakes are engaged for axes with `brake = true` whose drive is not enabled. Any other
//! frame is handled by the drives the moment it is sent; their answers are queued for the master's
//! next [`Bus::recv`]. Everything is deterministic: the same frames sent give the same frames
//! received and the same truth, bit for bit.
//!
//! Restart of the MCM: the drives keep their power while `mcm-rt` restarts, so
//! [`SimBus::save`] writes what survives that (per drive the encoder offset, the power-cycle
//! count and the stored calibration 0x2100; the arm's true joint angles) to a small text file
//! and [`SimBus::resume`] builds the bus again from it: the arm at rest at the saved angles, the
//! drives booting as after an NMT reset. Both run outside the cycle (they do file I/O).
//!
//! ```
//! use mcm_bus::Bus;
//! use mcm_sim::{SimCommand, SimControl};
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let mut bus = mcm_sim::SimBus::new(&cfg);
//! while bus.recv(0).unwrap().is_some() {} // boot-ups
//! let sim: &mut dyn SimControl = &mut bus;
//! sim.apply(&SimCommand { emergency_stop: Some(true), ..SimCommand::default() }).unwrap();
//! assert!(sim.truth().emergency_stop);
//! let nan = [f64::NAN; 6];
//! let bad = SimCommand { external_torques_nm: Some(nan), ..SimCommand::default() };
//! assert!(sim.apply(&bad).is_err());
//! ```

use super::drive::{DriveParams, Retained, SimDrive};
use super::{Discard, FrameSink};
use crate::physics::ArmSim;
use crate::{SimCommand, SimCommandError, SimControl, SimTruth};
use mcm_bus::{Bus, BusError, Frame};
use mcm_dynamics::ArmModel;
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;
use std::io;
use std::path::Path;

/// First line of a saved simulation state.
const STATE_HEADER: &str = "mcm-sim-state 1";

/// Frames the receive queue holds (several cycles' worth of traffic).
pub const RX_CAPACITY: usize = 512;
/// COB-ID of SYNC.
pub const SYNC_ID: u16 = 0x080;

/// Fixed-capacity FIFO of frames to the master (inline, no heap).
#[derive(Debug, Clone)]
struct RxRing {
    frames: heapless::Deque<Frame, RX_CAPACITY>,
    overruns: u64,
}

impl RxRing {
    fn new() -> RxRing {
        RxRing {
            frames: heapless::Deque::new(),
            overruns: 0,
        }
    }

    fn pop(&mut self) -> Option<Frame> {
        self.frames.pop_front()
    }
}

/// Where a drive's frames go: to the master (`connected`) or nowhere (its cable is cut).
fn sink<'a>(
    rx: &'a mut RxRing,
    discard: &'a mut Discard,
    connected: bool,
) -> &'a mut dyn FrameSink {
    if connected { rx } else { discard }
}

impl FrameSink for RxRing {
    fn emit(&mut self, frame: Frame) {
        if self.frames.push_back(frame).is_err() {
            self.overruns += 1;
        }
    }
}

/// The simulated robot on its bus.
pub struct SimBus {
    drives: [SimDrive; NUM_AXES],
    connected: [bool; NUM_AXES],
    brakes: [bool; NUM_AXES],
    torques: [f64; NUM_AXES],
    arm: ArmSim,
    rx: RxRing,
    emergency_stop: bool,
    now_ns: u64,
    period_ns: u64,
    substeps: u32,
    step_s: f64,
}

impl SimBus {
    /// The robot at power-up: the arm at `sim.initial_position_deg`, every drive booted (their
    /// boot-up frames are queued). `cfg` must be a validated configuration (six axes, a
    /// physics step dividing the cycle period), as `RobotConfig` loading guarantees.
    pub fn new(cfg: &RobotConfig) -> SimBus {
        let arm = ArmSim::new(ArmModel::from_config(cfg), cfg);
        let (q, v) = (arm.position(), arm.velocity());
        let mut rx = RxRing::new();
        let drives = core::array::from_fn(|i| {
            SimDrive::new(
                DriveParams::from_config(cfg, &cfg.axes[i]),
                q[i],
                v[i],
                &mut rx,
            )
        });
        let step_ns = u64::from(cfg.sim.physics_step_us.max(1)) * 1000;
        let period_ns = cfg.cycle_period_ns();
        let mut bus = SimBus {
            drives,
            connected: [true; NUM_AXES],
            brakes: [false; NUM_AXES],
            torques: [0.0; NUM_AXES],
            arm,
            rx,
            emergency_stop: false,
            now_ns: 0,
            period_ns,
            substeps: (period_ns / step_ns).max(1) as u32,
            step_s: step_ns as f64 * 1e-9,
        };
        bus.update_brakes();
        bus
    }

    /// Write what survives a restart of the MCM (the drives keep their power) to `path`: the
    /// arm's true joint angles and, per drive, power-cycle count, encoder offset and the
    /// stored calibration 0x2100. Plain text; not for the cycle (file I/O).
    pub fn save(&self, path: &Path) -> io::Result<()> {
        use std::fmt::Write as _;
        let mut text = String::new();
        let _ = writeln!(text, "{STATE_HEADER}");
        text.push_str("arm");
        for q in self.arm.position() {
            let _ = write!(text, " {q}");
        }
        text.push('\n');
        for (i, d) in self.drives.iter().enumerate() {
            let r = d.retained();
            let _ = writeln!(
                text,
                "drive {i} {} {} {} {}",
                r.power_cycles, r.encoder_offset_counts, r.calibration_offset, r.calibration_valid
            );
        }
        std::fs::write(path, text)
    }

    /// The robot as it was when [`SimBus::save`] wrote `path`, after a restart of the MCM:
    /// the arm at rest at the saved joint angles; every drive with its saved encoder offset,
    /// power-cycle count and stored calibration, booting as after an NMT reset node (boot-up
    /// frames queued, to be configured by the master). `Ok(None)` when `path` does not exist;
    /// `InvalidData` when it is not a saved state for six axes.
    pub fn resume(cfg: &RobotConfig, path: &Path) -> io::Result<Option<SimBus>> {
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(e),
        };
        let (q, kept) = parse_state(&text).map_err(|what| {
            io::Error::new(
                io::ErrorKind::InvalidData,
                format!("{}: not a saved simulation state: {what}", path.display()),
            )
        })?;
        let mut bus = SimBus::new(cfg);
        bus.arm.set_state(q, [0.0; NUM_AXES]);
        bus.rx = RxRing::new();
        let rx = &mut bus.rx;
        bus.drives = core::array::from_fn(|i| {
            SimDrive::resume(
                DriveParams::from_config(cfg, &cfg.axes[i]),
                q[i],
                0.0,
                kept[i],
                rx,
            )
        });
        bus.update_brakes();
        Ok(Some(bus))
    }

    /// Simulated time [ns]: cycle periods so far (SYNCs, and periods without one) x period.
    pub fn now_ns(&self) -> u64 {
        self.now_ns
    }

    /// The arm's physics (its true state, its mechanical stops), for inspection.
    pub fn arm(&self) -> &ArmSim {
        &self.arm
    }

    /// The drive of `axis` (0-based), for inspection.
    pub fn drive(&self, axis: usize) -> Option<&SimDrive> {
        self.drives.get(axis)
    }

    /// Frames dropped because the receive queue was full.
    pub fn rx_overruns(&self) -> u64 {
        self.rx.overruns
    }

    fn update_brakes(&mut self) {
        for (i, d) in self.drives.iter().enumerate() {
            let engaged = d.brake_engaged();
            if engaged != self.brakes[i] {
                self.arm.set_brake(i, engaged);
                self.brakes[i] = engaged;
            }
        }
    }

    /// One cycle period passes without SYNC reaching the drives (it was lost on the bus, or
    /// its producer is stuck): the physics and the drives' clocks advance as on SYNC, but no
    /// drive applies its latched RPDOs or samples and sends its TPDOs. The drives keep their
    /// last setpoint (CSP: the last target, held; CST: the last torque) and still send their
    /// heartbeats, which run on their own clocks. A fault injection for tests (the master never
    /// calls it): lock-step time needs the period to pass although the SYNC did not arrive.
    pub fn period_without_sync(&mut self) {
        self.period(false);
    }

    /// Switch off the supply of the drive of `axis` (0-based; others are ignored), the first
    /// half of a reboot of that drive alone: its power stage off at once (no current, the brake
    /// engaged), dead to the bus until [`SimBus::power_on_drive`].
    pub fn power_off_drive(&mut self, axis: usize) {
        if let Some(d) = self.drives.get_mut(axis) {
            d.power_off();
        }
        self.update_brakes();
    }

    /// The supply of the drive of `axis` is back: it boots as at power-up (object dictionary
    /// back to its defaults, 0x2100 cleared, a new encoder offset, its boot-up frame sent,
    /// PRE-OPERATIONAL, NOT READY TO SWITCH ON). Nothing for a drive that has power.
    pub fn power_on_drive(&mut self, axis: usize) {
        if let Some(d) = self.drives.get_mut(axis) {
            d.power_on(sink(&mut self.rx, &mut Discard, self.connected[axis]));
        }
        self.update_brakes();
    }

    /// One cycle period: the drives see the SYNC (`sync`, when their cable is in) or only
    /// their own clock, then the physics runs the period.
    fn period(&mut self, sync: bool) {
        let (q, v) = (self.arm.position(), self.arm.velocity());
        for (i, d) in self.drives.iter_mut().enumerate() {
            d.observe(q[i], v[i]);
            let connected = self.connected[i];
            d.on_sync(
                sync && connected,
                sink(&mut self.rx, &mut Discard, connected),
            );
        }
        for k in 0..self.substeps {
            let fraction = f64::from(k) / f64::from(self.substeps);
            let (q, v) = (self.arm.position(), self.arm.velocity());
            for (i, d) in self.drives.iter_mut().enumerate() {
                self.torques[i] = d.control(q[i], v[i], fraction, self.step_s);
            }
            self.update_brakes();
            self.arm.step(&self.torques, self.step_s);
        }
        for d in &mut self.drives {
            d.end_period();
        }
        self.now_ns += self.period_ns;
    }
}

/// Parse the text [`SimBus::save`] writes.
fn parse_state(text: &str) -> Result<([f64; NUM_AXES], [Retained; NUM_AXES]), String> {
    let mut lines = text.lines();
    if lines.next() != Some(STATE_HEADER) {
        return Err(format!("the first line is not {STATE_HEADER:?}"));
    }
    let mut q = [f64::NAN; NUM_AXES];
    let mut kept: [Option<Retained>; NUM_AXES] = [None; NUM_AXES];
    for line in lines {
        let words: Vec<&str> = line.split_whitespace().collect();
        let bad = || format!("bad line {line:?}");
        match words.as_slice() {
            [] => {}
            ["arm", angles @ ..] if angles.len() == NUM_AXES => {
                for (qi, w) in q.iter_mut().zip(angles) {
                    *qi = w
                        .parse()
                        .ok()
                        .filter(|v: &f64| v.is_finite())
                        .ok_or_else(bad)?;
                }
            }
            ["drive", i, pc, off, cal, valid] => {
                let i: usize = i.parse().ok().filter(|i| *i < NUM_AXES).ok_or_else(bad)?;
                kept[i] = Some(Retained {
                    power_cycles: pc.parse().map_err(|_| bad())?,
                    encoder_offset_counts: off.parse().map_err(|_| bad())?,
                    calibration_offset: cal.parse().map_err(|_| bad())?,
                    calibration_valid: valid.parse().ok().filter(|v| *v <= 1).ok_or_else(bad)?,
                });
            }
            _ => return Err(bad()),
        }
    }
    if q.iter().any(|v| v.is_nan()) {
        return Err("no line \"arm <6 joint angles>\"".into());
    }
    let mut out = [Retained {
        power_cycles: 0,
        encoder_offset_counts: 0,
        calibration_offset: 0,
        calibration_valid: 0,
    }; NUM_AXES];
    for (i, (o, k)) in out.iter_mut().zip(kept).enumerate() {
        *o = k.ok_or_else(|| format!("no line for drive {i}"))?;
    }
    Ok((q, out))
}

impl core::fmt::Debug for SimBus {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("SimBus")
            .field("now_ns", &self.now_ns)
            .field("connected", &self.connected)
            .field("emergency_stop", &self.emergency_stop)
            .field("queued", &self.rx.frames.len())
            .field("overruns", &self.rx.overruns)
            .finish_non_exhaustive()
    }
}

impl Bus for SimBus {
    fn send(&mut self, frame: &Frame) -> Result<(), BusError> {
        if frame.id == SYNC_ID {
            self.period(true);
            return Ok(());
        }
        for (i, d) in self.drives.iter_mut().enumerate() {
            if self.connected[i] {
                d.on_frame(frame, &mut self.rx);
            }
        }
        Ok(())
    }

    fn recv(&mut self, _deadline_ns: u64) -> Result<Option<Frame>, BusError> {
        Ok(self.rx.pop())
    }
}

impl SimControl for SimBus {
    /// Applies a fault injection. A refused command changes nothing.
    fn apply(&mut self, cmd: &SimCommand) -> Result<(), SimCommandError> {
        if let Some(tau) = cmd.external_torques_nm
            && let Some((index, &value)) = tau.iter().enumerate().find(|(_, t)| !t.is_finite())
        {
            return Err(SimCommandError::TorqueNotFinite { index, value });
        }
        if let Some(pressed) = cmd.emergency_stop {
            self.emergency_stop = pressed;
            for (i, d) in self.drives.iter_mut().enumerate() {
                d.set_safe_torque_off(pressed, sink(&mut self.rx, &mut Discard, self.connected[i]));
            }
        }
        if let Some(a) = cmd.disconnect_axis {
            self.connected[a.index()] = false;
        }
        if let Some(a) = cmd.reconnect_axis {
            self.connected[a.index()] = true;
        }
        if let Some(a) = cmd.block_axis {
            self.arm.set_blocked(a.index(), true);
        }
        if let Some(a) = cmd.unblock_axis {
            self.arm.set_blocked(a.index(), false);
        }
        if let Some(tau) = cmd.external_torques_nm {
            self.arm.set_external_torques(tau);
        }
        if let Some(t) = cmd.true_tool {
            self.arm.model_mut().set_tool(&t);
        }
        if cmd.power_cycle {
            for (i, d) in self.drives.iter_mut().enumerate() {
                d.power_cycle(sink(&mut self.rx, &mut Discard, self.connected[i]));
            }
        }
        self.update_brakes();
        Ok(())
    }

    fn truth(&self) -> SimTruth {
        SimTruth {
            position: self.arm.position(),
            velocity: self.arm.velocity(),
            emergency_stop: self.emergency_stop,
        }
    }
}

#[cfg(test)]
mod tests;
