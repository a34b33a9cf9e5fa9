//! The controller: operating modes, commands, reference generation, and what each drive is
//! asked to do.
//!
//! Runs inside the cycle. A deterministic function of its inputs: [`Controller::step`] takes
//! the controller time, the frames received from the bus and the commands received, and
//! produces the frames to send and the state (whose reply ring carries the replies). No
//! allocation, no locks, no I/O, no logging.
//!
//! Frames of reference: the drives work in raw encoder angles; the controller works in joint
//! angles, `joint = raw - offset`, where an axis's offset is found by calibration (0 until
//! then). The reference sent in a cycle is the one for the end of that cycle: the drives apply
//! it at the SYNC that closes the cycle and reach it one period later.
//!
//! The files of this module: `mod.rs` (the cycle and the state), `commands.rs` (what each
//! command does), `motion.rs` (the per-cycle reference of each motion).

mod commands;
mod motion;

use crate::calibration::AxisSettings;
use crate::canopen::{AxisFeedback, DriveRequest, FrameBuf, Master, MasterEvent};
use crate::params::JointParams;
use crate::pvt::PvtStream;
use crate::safety::{self, ActiveChecks, I2t, SafetyParams};
use crate::trajectory::JointSample;
use mcm_dynamics::ArmModel;
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode, RejectCode, ReplyStatus};
use mcm_shared::sample::{
    AXIS_CALIBRATED, AXIS_ENABLED, AXIS_FAULT, AXIS_I2T_DERATED, AXIS_ONLINE, CommandSample,
    ErrorRecord, Reply, STATE_ALL_CALIBRATED, STATE_ESTOP, STATE_PVT_STARVED, StateSample,
};
pub use motion::Motion;

/// How long a mode change waits at least for every drive to reach Operation Enabled.
const ENABLE_TIMEOUT_NS: u64 = 2_000_000_000;
/// Share of the model's friction that RELEASE and TORQUE_CONTROL compensate. Less than all of
/// it, so that an arm let go comes to rest instead of drifting on.
pub const FRICTION_COMPENSATION: f64 = 0.7;
/// Extra damping in RELEASE, as a multiple of each joint's viscous friction: an arm pushed and
/// let go comes to rest within a fraction of a second.
pub const RELEASE_DAMPING: f64 = 1.0;

/// A command whose reply comes later.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Waiting {
    client_id: u64,
    request_id: u64,
    kind: CommandKind,
}

impl Waiting {
    fn of(c: &CommandSample, kind: CommandKind) -> Waiting {
        Waiting {
            client_id: c.client_id,
            request_id: c.request_id,
            kind,
        }
    }
}

/// Enabling the drives before HOLD or a calibration begins.
#[derive(Debug, Clone, Copy)]
struct Enabling {
    waiting: Waiting,
    deadline_ns: u64,
    /// Calibration to start once enabled (`None`: plain `hold`).
    then_calibrate: Option<[Option<AxisSettings>; NUM_AXES]>,
}

/// The controller of one arm.
pub struct Controller {
    master: Master,
    p: JointParams,
    model: ArmModel,
    i2t: I2t,
    safety: SafetyParams,
    /// The emergency stop input of the last cycle (a press is reported once, on its edge).
    estop_seen: bool,
    /// An error was reported and not yet cleared by a successful `hold`: later trips of the
    /// same incident are not reported again.
    error_latched: bool,
    /// Calibration settings per axis: `[reverse][force_mechanical_stop]`.
    cal_settings: [[[AxisSettings; 2]; 2]; NUM_AXES],
    mode: Mode,
    /// Joint = raw - offset; `None` until calibrated.
    offsets: [Option<f64>; NUM_AXES],
    motion: Motion,
    /// The commanded reference of this cycle (joint frame).
    cmd: JointSample,
    /// The commanded positions of the last two cycles: `[k-1, k-2]`. The position measured in
    /// cycle k was sampled when the drives were reaching the command of cycle k-2.
    cmd_hist: [[f64; NUM_AXES]; 2],
    /// Joint torques commanded in the torque modes.
    cmd_torque: [f64; NUM_AXES],
    stream: PvtStream,
    starved: bool,
    enabling: Option<Enabling>,
    /// The calibrate command waiting for its reply.
    calibrating: Option<Waiting>,
    /// Drives the master reported lost, missing or failed (until configured or recovered).
    lost: [bool; NUM_AXES],
    enable_timeout_ns: u64,
    requests: [DriveRequest; NUM_AXES],
    current_limit: [f64; NUM_AXES],
    prev_velocity: [f64; NUM_AXES],
    acceleration: [f64; NUM_AXES],
    state: StateSample,
    cycle: u64,
    now_ns: u64,
}

impl Controller {
    /// Build the controller of the arm `cfg` describes, over the CANopen `master`.
    pub fn new(cfg: &RobotConfig, master: Master) -> Controller {
        let mut state = StateSample::default();
        let p = JointParams::from_config(cfg);
        let stream = PvtStream::new();
        state.pvt_capacity = stream.capacity() as u32;
        Controller {
            master,
            model: ArmModel::from_config(cfg),
            i2t: I2t::new(&SafetyParams::from_config(cfg)),
            safety: SafetyParams::from_config(cfg),
            estop_seen: false,
            error_latched: false,
            cal_settings: core::array::from_fn(|axis| {
                core::array::from_fn(|rev| {
                    core::array::from_fn(|force| {
                        AxisSettings::from_config(cfg, axis, rev == 1, force == 1)
                    })
                })
            }),
            mode: Mode::Off,
            offsets: [None; NUM_AXES],
            motion: Motion::Hold,
            cmd: JointSample::default(),
            cmd_hist: [[0.0; NUM_AXES]; 2],
            cmd_torque: [0.0; NUM_AXES],
            stream,
            starved: false,
            enabling: None,
            calibrating: None,
            lost: [false; NUM_AXES],
            enable_timeout_ns: ENABLE_TIMEOUT_NS
                .max(u64::from(cfg.bus.boot_timeout_ms) * 1_000_000),
            requests: [DriveRequest::Disable; NUM_AXES],
            current_limit: p.max_current,
            prev_velocity: [0.0; NUM_AXES],
            acceleration: [0.0; NUM_AXES],
            p,
            state,
            cycle: 0,
            now_ns: 0,
        }
    }

    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The state sample as of the last step (replies included).
    pub fn state(&self) -> &StateSample {
        &self.state
    }

    /// The state sample, for the edges to add timing and simulation truth before publishing.
    pub fn state_mut(&mut self) -> &mut StateSample {
        &mut self.state
    }

    /// The drive feedback of the last step.
    pub fn feedback(&self) -> &[AxisFeedback; NUM_AXES] {
        self.master.feedback()
    }

    /// Calibration offsets (joint = raw - offset) [rad].
    pub fn offsets(&self) -> [Option<f64>; NUM_AXES] {
        self.offsets
    }

    /// Append a reply to the state's reply ring (also used by the simulator's edge,
    /// [`crate::sim_edge`], for `sim` commands).
    pub fn push_reply(&mut self, reply: Reply) {
        self.state.push_reply(reply);
    }

    /// One cycle: `now_ns` is controller time (cycle index x period); `rx` the frames received
    /// since the last cycle; `commands` the commands received. Frames to send are appended to
    /// `tx`, SYNC last.
    pub fn step(
        &mut self,
        now_ns: u64,
        rx: &[mcm_bus::Frame],
        commands: &[CommandSample],
        tx: &mut FrameBuf,
    ) {
        self.cycle += 1;
        self.now_ns = now_ns;
        for f in rx {
            self.master.handle_frame(now_ns, f);
        }
        while let Some(ev) = self.master.poll_event() {
            self.on_event(ev);
        }
        for c in commands {
            self.on_command(c);
        }
        self.update_enabling();
        self.check_safety();
        self.cmd_hist = [self.cmd.position, self.cmd_hist[0]];
        self.advance_motion();
        self.update_i2t();
        self.master
            .cycle(now_ns, &self.requests, &self.current_limit, tx);
        self.fill_state();
    }

    /// Measured joint positions.
    fn measured(&self) -> [f64; NUM_AXES] {
        let fb = self.master.feedback();
        core::array::from_fn(|i| fb[i].position_rad - self.offsets[i].unwrap_or(0.0))
    }

    fn measured_velocity(&self) -> [f64; NUM_AXES] {
        let fb = self.master.feedback();
        core::array::from_fn(|i| fb[i].velocity_rad_s)
    }

    fn reply(
        &mut self,
        w: Waiting,
        status: ReplyStatus,
        code: RejectCode,
        axis: u32,
        values: &[f64],
    ) {
        let mut r = Reply {
            client_id: w.client_id,
            request_id: w.request_id,
            kind: w.kind.to_wire(),
            status: status.to_wire(),
            code: code.to_wire(),
            axis,
            ..Reply::default()
        };
        let n = values.len().min(r.values.len());
        r.values[..n].copy_from_slice(&values[..n]);
        self.state.push_reply(r);
    }

    /// A reason the drives cannot be enabled now: emergency stop, or a drive the master gave
    /// up on (a drive still booting is waited for).
    fn enable_blocker(&self) -> Option<(RejectCode, u32)> {
        let fb = self.master.feedback();
        if fb.iter().any(|f| f.estop) {
            return Some((RejectCode::EmergencyStop, 0));
        }
        self.lost
            .iter()
            .position(|l| *l)
            .map(|i| (RejectCode::DriveDisconnected, i as u32 + 1))
    }

    /// Start enabling every drive, holding where it is.
    fn begin_enabling(
        &mut self,
        waiting: Waiting,
        then_calibrate: Option<[Option<AxisSettings>; NUM_AXES]>,
    ) {
        if let Some(prev) = self.enabling.take() {
            self.reply(
                prev.waiting,
                ReplyStatus::Failed,
                RejectCode::Aborted,
                0,
                &[],
            );
        }
        self.master.reset_faults();
        self.hold_here();
        self.enabling = Some(Enabling {
            waiting,
            deadline_ns: self.now_ns + self.enable_timeout_ns,
            then_calibrate,
        });
    }

    fn update_enabling(&mut self) {
        let Some(e) = self.enabling else { return };
        let fb = self.master.feedback();
        if fb.iter().all(|f| f.enabled) {
            self.enabling = None;
            match e.then_calibrate {
                None => {
                    self.mode = Mode::Hold;
                    self.error_latched = false;
                    self.hold_here();
                    self.reply(e.waiting, ReplyStatus::Ok, RejectCode::None, 0, &[]);
                }
                Some(settings) => self.start_calibration(e.waiting, settings),
            }
        } else if let Some((code, axis)) = self.enable_blocker() {
            self.enabling = None;
            self.reply(e.waiting, ReplyStatus::Failed, code, axis, &[]);
        } else if self.now_ns >= e.deadline_ns {
            self.enabling = None;
            let axis = fb
                .iter()
                .position(|f| !f.enabled)
                .map_or(0, |i| i as u32 + 1);
            self.reply(
                e.waiting,
                ReplyStatus::Failed,
                RejectCode::DriveFault,
                axis,
                &[],
            );
        }
    }

    /// Hold every axis at its measured position, at rest.
    fn hold_here(&mut self) {
        self.cmd = JointSample {
            position: self.measured(),
            ..JointSample::default()
        };
        self.cmd_hist = [self.cmd.position; 2];
        self.motion = Motion::Hold;
    }

    fn on_event(&mut self, ev: MasterEvent) {
        match ev {
            MasterEvent::Lost { axis, .. } | MasterEvent::Missing { axis, .. } => {
                self.lost[axis] = true;
                self.trip(RejectCode::DriveDisconnected, axis, [0.0; 4]);
            }
            MasterEvent::Recovered { axis, .. } | MasterEvent::Configured { axis } => {
                self.lost[axis] = false;
            }
            MasterEvent::Emcy { axis, emcy } => {
                if emcy.code != 0 {
                    self.drive_fault(axis, emcy.code);
                }
            }
            MasterEvent::Fault { axis, code } => self.drive_fault(axis, code),
            MasterEvent::ConfigFailed { axis, .. } => {
                self.lost[axis] = true;
                self.trip(RejectCode::DriveDisconnected, axis, [0.0; 4]);
            }
            MasterEvent::Booted { axis } => {
                // Calibration is gone unless the drive still holds it (below): a drive that
                // boots after a power cycle lost its encoder reference.
                self.offsets[axis] = None;
                if self.mode != Mode::Off {
                    self.trip(RejectCode::DriveDisconnected, axis, [0.0; 4]);
                }
            }
            // Comes after `Booted` (and `Configured`) of the same boot: the calibration the
            // drive kept (0x2100) while the MCM restarted.
            MasterEvent::Calibration {
                axis,
                offset_counts,
            } => {
                self.offsets[axis] =
                    offset_counts.map(|c| f64::from(c) / self.p.counts_per_rad[axis]);
            }
            // Storing failed: the calibration holds until the MCM restarts (nothing to stop).
            MasterEvent::CalibrationStored { .. } | MasterEvent::CalibrationStoreFailed { .. } => {}
        }
    }

    /// A drive reports a fault: the emergency stop (which cuts the drives' power) when its
    /// input is active, a drive fault otherwise.
    fn drive_fault(&mut self, axis: usize, code: u16) {
        if self.master.feedback().iter().any(|f| f.estop) {
            self.estop_seen = true;
            self.trip_axis(RejectCode::EmergencyStop, 0, [1.0, 0.0, 0.0, 0.0]);
        } else {
            self.trip(
                RejectCode::DriveFault,
                axis,
                [f64::from(code), 0.0, 0.0, 0.0],
            );
        }
    }

    /// The checks of the manual's "Safety checks" evaluated every cycle (drive connections
    /// come as master events).
    fn check_safety(&mut self) {
        let estop = self.master.feedback().iter().any(|f| f.estop);
        if estop && !self.estop_seen {
            self.estop_seen = true;
            self.trip_axis(RejectCode::EmergencyStop, 0, [1.0, 0.0, 0.0, 0.0]);
        }
        self.estop_seen = estop;
        if self.enabling.is_some()
            || !matches!(
                self.mode,
                Mode::Hold | Mode::Pvt | Mode::Release | Mode::TorqueControl
            )
        {
            return;
        }
        let active = ActiveChecks::for_mode(self.mode);
        let q = self.measured();
        let qd = self.measured_velocity();
        let mut result = Ok(());
        if active.limits {
            result = result
                .and_then(|()| safety::check_position_limits_returning(&self.safety, &q, &qd))
                .and_then(|()| safety::check_velocity_limits(&self.safety, &qd));
        }
        // A planned move or stop is validated when planned: it ends inside the reachable range
        // at the deceleration it plans with; the braking check watches everything else.
        if active.braking && !matches!(self.motion, Motion::Move { .. } | Motion::Stop { .. }) {
            result = result.and_then(|()| safety::check_braking(&self.safety, &q, &qd));
        }
        if active.following {
            result = result
                .and_then(|()| safety::check_following_error(&self.safety, &self.cmd_hist[1], &q));
        }
        if let Err(v) = result {
            let [value, limit] = v.user_values();
            self.trip(v.check.reject_code(), v.axis, [value, limit, 0.0, 0.0]);
        }
    }

    /// A safety check or drive error: mode ERROR (from any mode but OFF, where nothing moves
    /// and the error is only reported), axes stopped, and one spontaneous error record per
    /// incident (until a `hold` succeeds).
    fn trip(&mut self, code: RejectCode, axis0: usize, values: [f64; 4]) {
        self.trip_axis(code, axis0 as u32 + 1, values);
    }

    /// [`Controller::trip`] with a 1-based axis (0: no axis).
    fn trip_axis(&mut self, code: RejectCode, axis: u32, values: [f64; 4]) {
        if let Some(w) = self.calibrating.take() {
            self.reply(w, ReplyStatus::Failed, code, axis, &values);
        }
        if let Some(e) = self.enabling.take() {
            self.reply(e.waiting, ReplyStatus::Failed, code, axis, &values);
        }
        if self.mode != Mode::Off {
            if self.mode != Mode::Error {
                self.quick_stop();
            }
            self.mode = Mode::Error;
        }
        if self.error_latched {
            return;
        }
        self.error_latched = true;
        let e = &mut self.state.last_error;
        *e = ErrorRecord {
            seq: e.seq + 1,
            cycle: self.cycle,
            unix_ns: 0,
            code: code.to_wire(),
            axis,
            values,
        };
    }

    fn update_i2t(&mut self) {
        let fb = self.master.feedback();
        let currents: [f64; NUM_AXES] = core::array::from_fn(|i| fb[i].current_a);
        self.i2t.update(&currents, self.p.period);
        let i2t_max = self.i2t.max_current();
        for (limit, i2t) in self.current_limit.iter_mut().zip(i2t_max) {
            *limit = limit.min(i2t);
        }
    }

    fn fill_state(&mut self) {
        let fb = *self.master.feedback();
        let measured = self.measured();
        let s = &mut self.state;
        s.seq = self.cycle;
        s.t_ns = self.now_ns;
        s.mode = self.mode.to_wire();
        let mut flags = s.flags & !(STATE_ESTOP | STATE_ALL_CALIBRATED | STATE_PVT_STARVED);
        if fb.iter().any(|f| f.estop) {
            flags |= STATE_ESTOP;
        }
        if self.offsets.iter().all(Option::is_some) {
            flags |= STATE_ALL_CALIBRATED;
        }
        if self.starved {
            flags |= STATE_PVT_STARVED;
        }
        s.flags = flags;
        s.pvt_queued = self.stream.queued() as u32;
        let torque_mode = matches!(self.mode, Mode::Release | Mode::TorqueControl);
        let level = self.i2t.level();
        let derated = self.i2t.derated();
        for (i, f) in fb.iter().enumerate() {
            let v = f.velocity_rad_s;
            let a = (v - self.prev_velocity[i]) / self.p.period;
            self.prev_velocity[i] = v;
            // A light low-pass: differentiated velocity is noisy.
            self.acceleration[i] += 0.2 * (a - self.acceleration[i]);
            let (pos, vel, acc, cur) = match self.mode {
                Mode::Pvt => (
                    self.cmd.position[i],
                    self.cmd.velocity[i],
                    self.cmd.acceleration[i],
                    f.current_a,
                ),
                _ if torque_mode => (
                    measured[i],
                    v,
                    self.acceleration[i],
                    self.cmd_torque[i] / self.p.torque_per_amp[i],
                ),
                _ => (measured[i], v, self.acceleration[i], f.current_a),
            };
            s.position[i] = pos.to_degrees();
            s.velocity[i] = vel.to_degrees();
            s.acceleration[i] = acc.to_degrees();
            s.current[i] = cur;
            s.measured_position[i] = measured[i].to_degrees();
            s.commanded_position[i] = self.cmd.position[i].to_degrees();
            s.following_error[i] = (self.cmd_hist[1][i] - measured[i]).to_degrees();
            s.i2t[i] = level[i];
            let mut af = 0;
            if f.online {
                af |= AXIS_ONLINE;
            }
            if f.enabled {
                af |= AXIS_ENABLED;
            }
            if f.state.is_fault() {
                af |= AXIS_FAULT;
            }
            if self.offsets[i].is_some() {
                af |= AXIS_CALIBRATED;
            }
            if derated[i] {
                af |= AXIS_I2T_DERATED;
            }
            s.axis_flags[i] = af;
        }
    }
}

#[cfg(test)]
mod tests;
