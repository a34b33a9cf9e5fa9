//! One simulated CiA 402 servo drive (`docs/drive-profile.md`, "The simulated drive"): object
//! dictionary, expedited SDO server, NMT slave with heartbeat producer and master-heartbeat
//! consumer, PDO engine, CiA 402 state machine, and the motor: CSP position loop, CST torque,
//! current limit 0x6073, incremental encoder with a random offset drawn at every power-up, and the
//! stored calibration 0x2100 (see [`od`]), which only a power cycle clears.
//!
//! Runs inside the cycle: no allocation after construction, no panics on bad frames. The
//! drive's clock advances only through SYNC ([`SimDrive::end_period`]); the bus drives it:
//!
//! ```
//! use mcm_sim::{Discard, drive::{DriveParams, SimDrive}};
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let mut d = SimDrive::new(DriveParams::from_config(&cfg, &cfg.axes[0]), 0.0, 0.0, &mut Discard);
//! d.on_sync(true, &mut Discard); // at SYNC: RPDOs applied, TPDOs sent
//! for k in 0..10 {
//!     let _joint_torque = d.control(0.0, 0.0, k as f64 / 10.0, 0.0005); // physics sub-steps
//! }
//! d.end_period();
//! assert_eq!(d.time_ns(), 5_000_000);
//! ```

use super::FrameSink;
use super::cia402::{State, StateMachine, StatusInputs, Transition};
use super::nmt::{self, HeartbeatConsumer, HeartbeatProducer, NmtCommand, NmtState};
use super::od::{self, Od, OdDefaults};
use super::pdo::{PdoEngine, PdoWrites, RxOutcome};
use super::sdo_server;
use super::servo::{Servo, ServoGains};
use mcm_bus::Frame;
use mcm_shared::config::{AxisConfig, RobotConfig};

/// COB-ID base of EMCY frames.
pub const EMCY_BASE: u16 = 0x080;
/// EMCY code and error register: master heartbeat lost.
pub const EMCY_HEARTBEAT: (u16, u8) = (0x8130, 0x11);
/// EMCY code and error register: no SYNC (so no setpoint applied) for [`SYNC_LOSS_PERIODS`]
/// while enabled: RPDO timeout, a communication error.
pub const EMCY_SYNC_LOSS: (u16, u8) = (0x8250, 0x11);
/// EMCY code and error register: the connection to the master aborted (its NMT stop) with the
/// abort connection option 1 (fault). Recorded in 0x603F; no EMCY goes out while STOPPED.
pub const EMCY_ABORT_CONNECTION: (u16, u8) = (0x8100, 0x11);
/// Periods in OPERATION ENABLED without a SYNC after which the drive faults (0.3 s at 200 Hz).
/// Without SYNC a drive applies no setpoint (its RPDO1 is latched until the next SYNC), so the
/// master can neither move nor disable it; faulting powers the motor off onto its brake, as a
/// lost master heartbeat does. Longer than the master heartbeat's consumer time (0.15 s), so a
/// cut cable faults on the heartbeat first.
pub const SYNC_LOSS_PERIODS: u32 = 60;
/// EMCY code and error register: safe torque off (emergency stop) while enabled.
pub const EMCY_SAFE_TORQUE_OFF: (u16, u8) = (0x5441, 0x05);
/// Modes of operation.
pub const MODE_CSP: i8 = 8;
pub const MODE_CST: i8 = 10;
/// 0x1011:1 signature "load".
const RESTORE_SIGNATURE: u32 = 0x6461_6F6C;

/// Everything a drive needs to know about its axis, taken from the configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveParams {
    pub node_id: u8,
    /// Encoder counts per joint radian.
    pub counts_per_rad: f64,
    /// Motor torque constant [Nm/A].
    pub torque_constant: f64,
    /// Joint torque per motor ampere [Nm/A].
    pub torque_per_amp: f64,
    /// Hardware peak current [A].
    pub peak_current_a: f64,
    pub brake: bool,
    /// Joint angle of the light barrier [rad], if the axis has one.
    pub light_barrier_rad: Option<f64>,
    /// Quick-stop deceleration [rad/s^2] (the axis's maximum acceleration).
    pub quick_stop_deceleration: f64,
    pub gains: ServoGains,
    /// `sim.seed`, for the encoder offsets.
    pub seed: u64,
    /// Largest encoder offset [rad of joint angle].
    pub max_encoder_offset_rad: f64,
    /// SYNC period [ns].
    pub period_ns: u64,
    pub od_defaults: OdDefaults,
}

impl DriveParams {
    /// The drive of `axis` (one of `cfg.axes`).
    pub fn from_config(cfg: &RobotConfig, axis: &AxisConfig) -> DriveParams {
        let peak_permille = (axis.max_current_a / axis.rated_current_a * 1000.0)
            .ceil()
            .min(f64::from(u16::MAX));
        DriveParams {
            node_id: axis.node_id,
            counts_per_rad: axis.counts_per_rad(),
            torque_constant: axis.torque_constant_nm_a,
            torque_per_amp: axis.torque_per_amp(),
            peak_current_a: axis.max_current_a,
            brake: axis.brake,
            light_barrier_rad: axis.calibration.light_barrier_deg.map(f64::to_radians),
            quick_stop_deceleration: axis.max_acceleration_deg_s2.to_radians(),
            gains: ServoGains::for_armature(axis.armature_kg_m2),
            seed: cfg.sim.seed,
            max_encoder_offset_rad: cfg.sim.max_encoder_offset_deg.to_radians(),
            period_ns: cfg.cycle_period_ns(),
            od_defaults: OdDefaults {
                node_id: axis.node_id,
                rated_current_ma: (axis.rated_current_a * 1000.0).round() as u32,
                rated_torque_mnm: (axis.torque_constant_nm_a * axis.rated_current_a * 1000.0)
                    .round() as u32,
                peak_current_permille: peak_permille as u16,
            },
        }
    }
}

fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The encoder offset [counts] drawn at power-up number `power_cycle` of node `node_id`:
/// uniform in +-`max_offset_rad` of joint angle, from SplitMix64 of (seed, node, power cycle).
pub fn encoder_offset_counts(
    seed: u64,
    node_id: u8,
    power_cycle: u64,
    max_offset_rad: f64,
    counts_per_rad: f64,
) -> i64 {
    let h = splitmix64(splitmix64(seed ^ (u64::from(node_id) << 56)) ^ power_cycle);
    let unit = (h >> 11) as f64 / (1u64 << 53) as f64; // [0, 1)
    ((2.0 * unit - 1.0) * max_offset_rad * counts_per_rad).round() as i64
}

/// What a drive keeps while only the MCM restarts (the drive keeps its power): saved and
/// restored by [`super::SimBus::save`] / [`super::SimBus::resume`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Retained {
    /// Power-ups so far after the first (draws the next encoder offset).
    pub power_cycles: u64,
    /// The encoder offset of this power-up [counts].
    pub encoder_offset_counts: i64,
    /// 0x2100:1, the stored calibration offset [counts].
    pub calibration_offset: i32,
    /// 0x2100:2, the stored calibration is valid (0/1).
    pub calibration_valid: u8,
}

enum Boot {
    PowerUp,
    ResetNode,
    ResetCommunication,
}

/// What a drive saw go wrong on its bus since power-up: the figures a drive's diagnostics
/// would give, to judge a bus from the drives' side; and, not a fault, the loop restarts it
/// was asked for.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DriveCounters {
    /// SYNCs received in OPERATION ENABLED without an RPDO1 (the setpoint) since the last one:
    /// a setpoint lost or late.
    pub rpdo1_missing: u64,
    /// SDO requests answered with an abort.
    pub sdo_aborts: u64,
    /// The master's heartbeat missing for longer than the consumer time (0x1016).
    pub heartbeat_timeouts: u64,
    /// Faults for want of SYNC while enabled ([`SYNC_LOSS_PERIODS`]).
    pub sync_losses: u64,
    /// NMT stops while OPERATIONAL, each met with the abort connection reaction (0x6007).
    pub connection_aborts: u64,
    /// Restarts of the CSP loop where the joint stands (a fault-reset edge while OPERATION
    /// ENABLED, the MCM drive profile).
    pub loop_restarts: u64,
}

/// One simulated drive.
#[derive(Debug, Clone)]
pub struct SimDrive {
    p: DriveParams,
    od: Od,
    nmt: NmtState,
    producer: HeartbeatProducer,
    consumer: HeartbeatConsumer,
    pdo: PdoEngine,
    sm: StateMachine,
    servo: Servo,
    time_ns: u64,
    power_cycles: u64,
    offset_counts: i64,
    safe_torque_off: bool,
    /// The drive's supply is on ([`SimDrive::power_off`] turns it off until
    /// [`SimDrive::power_on`]).
    powered: bool,
    joint_position: f64,
    encoder_counts: i64,
    velocity: f64,
    current_a: f64,
    last_setpoint: (f64, f64),
    counters: DriveCounters,
    /// Periods in OPERATION ENABLED since the last SYNC received.
    without_sync: u32,
}

impl SimDrive {
    /// Power up (power-up number 0) with the joint at `q` [rad], `v` [rad/s]; the boot-up
    /// frame goes to `out`.
    pub fn new(p: DriveParams, q: f64, v: f64, out: &mut dyn FrameSink) -> SimDrive {
        let mut d = SimDrive {
            p,
            od: Od::new(&p.od_defaults),
            nmt: NmtState::PreOperational,
            producer: HeartbeatProducer::default(),
            consumer: HeartbeatConsumer::default(),
            pdo: PdoEngine::default(),
            sm: StateMachine::new(),
            servo: Servo::new(p.gains),
            time_ns: 0,
            power_cycles: 0,
            offset_counts: 0,
            safe_torque_off: false,
            powered: true,
            joint_position: q,
            encoder_counts: 0,
            velocity: v,
            current_a: 0.0,
            last_setpoint: (0.0, 0.0),
            counters: DriveCounters::default(),
            without_sync: 0,
        };
        d.boot(Boot::PowerUp, out);
        d.observe(q, v);
        d
    }

    /// A drive that kept its power while the MCM restarted: encoder offset, power-cycle count
    /// and the stored calibration 0x2100 from `r`, everything else as after NMT reset node
    /// (boot-up frame to `out`, PRE-OPERATIONAL, NOT READY TO SWITCH ON).
    pub fn resume(
        p: DriveParams,
        q: f64,
        v: f64,
        r: Retained,
        out: &mut dyn FrameSink,
    ) -> SimDrive {
        let mut d = SimDrive::new(p, q, v, &mut super::Discard);
        d.power_cycles = r.power_cycles;
        d.offset_counts = r.encoder_offset_counts;
        d.od.set_i32(od::CALIBRATION_OFFSET, r.calibration_offset);
        d.od.set_raw(od::CALIBRATION_VALID, u32::from(r.calibration_valid));
        d.boot(Boot::ResetNode, out);
        d.observe(q, v);
        d
    }

    /// What this drive keeps while only the MCM restarts.
    pub fn retained(&self) -> Retained {
        Retained {
            power_cycles: self.power_cycles,
            encoder_offset_counts: self.offset_counts,
            calibration_offset: self.od.i32(od::CALIBRATION_OFFSET),
            calibration_valid: self.od.raw(od::CALIBRATION_VALID) as u8,
        }
    }

    /// Power off and on again: defaults (the stored calibration 0x2100 too), new encoder offset,
    /// boot-up frame, NOT READY TO SWITCH ON (SWITCH ON DISABLED at the next SYNC).
    pub fn power_cycle(&mut self, out: &mut dyn FrameSink) {
        self.power_off();
        self.power_on(out);
    }

    /// The drive's supply fails (a reboot begins): the power stage is off at once (no current,
    /// the brake engaged) and the drive is dead to the bus (it handles no frame and sends
    /// nothing, heartbeats included) until [`SimDrive::power_on`].
    pub fn power_off(&mut self) {
        self.powered = false;
        self.sm = StateMachine::new();
        self.current_a = 0.0;
        self.nmt = NmtState::PreOperational;
        self.pdo.stop();
        self.producer = HeartbeatProducer::default();
        self.consumer = HeartbeatConsumer::default();
    }

    /// The supply is back: the drive boots as at power-up (object dictionary defaults, the
    /// stored calibration 0x2100 cleared, a new encoder offset), sends its boot-up frame to
    /// `out` and is PRE-OPERATIONAL, NOT READY TO SWITCH ON. Nothing when it is powered.
    pub fn power_on(&mut self, out: &mut dyn FrameSink) {
        if self.powered {
            return;
        }
        self.powered = true;
        self.power_cycles += 1;
        self.boot(Boot::PowerUp, out);
        self.observe(self.joint_position, self.velocity);
    }

    /// Whether the drive's supply is on.
    pub fn powered(&self) -> bool {
        self.powered
    }

    fn boot(&mut self, kind: Boot, out: &mut dyn FrameSink) {
        match kind {
            Boot::PowerUp => {
                self.od = Od::new(&self.p.od_defaults);
                self.sm = StateMachine::new();
                self.offset_counts = encoder_offset_counts(
                    self.p.seed,
                    self.p.node_id,
                    self.power_cycles,
                    self.p.max_encoder_offset_rad,
                    self.p.counts_per_rad,
                );
            }
            Boot::ResetNode => {
                self.od.reset_communication();
                self.od.reset_application();
                self.sm = StateMachine::new();
            }
            Boot::ResetCommunication => self.od.reset_communication(),
        }
        if !self.sm.state().is_enabled() {
            self.current_a = 0.0;
        }
        self.nmt = NmtState::PreOperational;
        self.pdo.stop();
        self.producer = HeartbeatProducer::default();
        self.consumer = HeartbeatConsumer::default();
        out.emit(nmt::boot_up_frame(self.p.node_id));
    }

    /// What went wrong on the bus, as this drive saw it, since power-up (kept through a reset
    /// node or a power cycle: the simulation's diagnostics, not the drive's dictionary).
    pub fn counters(&self) -> DriveCounters {
        self.counters
    }

    pub fn node_id(&self) -> u8 {
        self.p.node_id
    }
    pub fn state(&self) -> State {
        self.sm.state()
    }
    pub fn nmt_state(&self) -> NmtState {
        self.nmt
    }
    /// The object dictionary (read-only view).
    pub fn od(&self) -> &Od {
        &self.od
    }
    /// The encoder offset of this power-up [counts]: position actual = q * counts_per_rad + offset.
    pub fn encoder_offset_counts(&self) -> i64 {
        self.offset_counts
    }
    /// The drive's own clock [ns] (advanced by SYNC).
    pub fn time_ns(&self) -> u64 {
        self.time_ns
    }
    /// Motor current of the last control step [A].
    pub fn current_a(&self) -> f64 {
        self.current_a
    }
    /// The holding brake is engaged (axes with a brake, while the drive is not enabled).
    pub fn brake_engaged(&self) -> bool {
        self.p.brake && (self.safe_torque_off || !self.sm.state().is_enabled())
    }

    /// Update the encoder from the true joint state.
    pub fn observe(&mut self, q: f64, v: f64) {
        self.joint_position = q;
        self.velocity = v;
        self.encoder_counts = (q * self.p.counts_per_rad).round() as i64 + self.offset_counts;
    }

    fn encoder_position(&self) -> f64 {
        self.encoder_counts as f64 / self.p.counts_per_rad
    }

    fn mode(&self) -> i8 {
        self.od.i32(od::MODES_DISPLAY) as i8
    }

    /// A frame from the bus (not SYNC), handled at once.
    pub fn on_frame(&mut self, f: &Frame, out: &mut dyn FrameSink) {
        if !self.powered {
            return;
        }
        self.consumer.on_frame(f, self.time_ns);
        if let Some(cmd) = NmtCommand::decode(f, self.p.node_id) {
            self.nmt_command(cmd, out);
            return;
        }
        let node = self.p.node_id;
        if f.id == sdo_server::SDO_RX_BASE + u16::from(node) {
            if self.nmt.sdo_allowed() {
                let mut ctx = objects::SdoContext { drive: self, out };
                if let Some(resp) = sdo_server::serve(node, f, &mut ctx) {
                    if resp.payload().first() == Some(&0x80) {
                        ctx.drive.counters.sdo_aborts += 1;
                    }
                    ctx.out.emit(resp);
                }
                self.emit_events(out);
            }
            return;
        }
        if self.nmt == NmtState::Operational {
            if let RxOutcome::Apply(w) = self.pdo.on_frame(&self.od, f) {
                self.apply_pdo(w, out);
            }
            self.emit_events(out);
        }
    }

    fn nmt_command(&mut self, cmd: NmtCommand, out: &mut dyn FrameSink) {
        match cmd {
            NmtCommand::Start if self.nmt != NmtState::Operational => {
                self.nmt = NmtState::Operational;
                self.pdo.start();
                self.emit_events(out);
            }
            NmtCommand::Start => {}
            NmtCommand::Stop => {
                let was_operational = self.nmt == NmtState::Operational;
                self.nmt = NmtState::Stopped;
                self.pdo.stop();
                if was_operational {
                    self.abort_connection(out);
                }
            }
            NmtCommand::EnterPreOperational => {
                self.nmt = NmtState::PreOperational;
                self.pdo.stop();
            }
            NmtCommand::ResetNode => self.boot(Boot::ResetNode, out),
            NmtCommand::ResetCommunication => self.boot(Boot::ResetCommunication, out),
        }
    }

    /// The master cut the connection (NMT stop while OPERATIONAL): the reaction its abort
    /// connection option code 0x6007 selects (CiA 402), at once, SYNC or not. A master that no
    /// longer reaches the drive by SYNC can still power it off this way.
    fn abort_connection(&mut self, out: &mut dyn FrameSink) {
        self.counters.connection_aborts += 1;
        let t = match self.od.i32(od::ABORT_CONNECTION_OPTION) {
            1 => {
                self.raise_fault(EMCY_ABORT_CONNECTION, out);
                return;
            }
            2 => self.sm.write_controlword(0, !self.safe_torque_off),
            3 => self.sm.write_controlword(0x0002, !self.safe_torque_off),
            _ => None,
        };
        self.on_transition(t, out);
    }

    /// A SYNC period begins: SYNC received (`received`), or a period of the drive's own clock
    /// without it (its cable cut, or the SYNC lost on the bus: `received = false`). Apply
    /// latched RPDOs (only on a SYNC received), check the master's heartbeat, start the next
    /// interpolation segment (without a SYNC: towards the same target, so the last setpoint is
    /// held), sample, send TPDOs (only on a SYNC received) and the heartbeat when due. Nothing
    /// while the drive has no power.
    pub fn on_sync(&mut self, received: bool, out: &mut dyn FrameSink) {
        if !self.powered {
            return;
        }
        let t = self.sm.boot_complete();
        self.on_transition(t, out);
        if received && self.nmt == NmtState::Operational {
            let latched = self.pdo.take_latched(&self.od);
            if latched[0].is_none() && self.sm.state() == State::OperationEnabled {
                self.counters.rpdo1_missing += 1;
            }
            for w in latched.into_iter().flatten() {
                self.apply_pdo(w, out);
            }
        }
        let t = self.sm.reevaluate(!self.safe_torque_off);
        self.on_transition(t, out);
        if self.consumer.expired(self.time_ns) {
            self.counters.heartbeat_timeouts += 1;
            self.raise_fault(EMCY_HEARTBEAT, out);
        }
        if received || self.sm.state() != State::OperationEnabled {
            self.without_sync = 0;
        } else {
            self.without_sync += 1;
            if self.without_sync >= SYNC_LOSS_PERIODS {
                self.without_sync = 0;
                self.counters.sync_losses += 1;
                self.raise_fault(EMCY_SYNC_LOSS, out);
            }
        }
        if self.sm.state() == State::OperationEnabled && self.mode() == MODE_CSP {
            let target = f64::from(self.od.i32(od::TARGET_POSITION)) / self.p.counts_per_rad;
            self.servo
                .new_segment(target, self.p.period_ns as f64 * 1e-9);
        }
        self.sample();
        if received && self.nmt == NmtState::Operational {
            for f in self.pdo.sync_tx(&self.od).into_iter().flatten() {
                out.emit(f);
            }
        }
        // Event-driven TPDOs (a change, or their event timer run out) go on the drive's own
        // clock, SYNC or not.
        self.emit_events(out);
        if self.producer.due(self.time_ns) {
            out.emit(nmt::heartbeat_frame(
                self.p.node_id,
                self.nmt.heartbeat_byte(),
            ));
        }
    }

    /// One physics sub-step at `fraction` (0..1) of the period: measure the true joint state,
    /// compute the motor current; returns the joint torque [Nm].
    pub fn control(&mut self, q: f64, v: f64, fraction: f64, dt: f64) -> f64 {
        self.observe(q, v);
        self.current_a = self.current_command(fraction, dt);
        self.current_a * self.p.torque_per_amp
    }

    /// The end of the SYNC period: the drive's clock advances by one period.
    pub fn end_period(&mut self) {
        self.time_ns += self.p.period_ns;
    }

    /// The emergency switch (safe torque off input) changed.
    pub fn set_safe_torque_off(&mut self, active: bool, out: &mut dyn FrameSink) {
        self.safe_torque_off = active;
        if active {
            let t = self.sm.power_stage_off();
            if let Some((_, State::Fault)) = t {
                self.record_fault(EMCY_SAFE_TORQUE_OFF, out);
            }
            self.on_transition(t, out);
        }
    }

    fn current_limit(&self) -> f64 {
        let permille = f64::from(self.od.raw(od::MAX_CURRENT));
        let rated = f64::from(self.od.raw(od::RATED_CURRENT)) / 1000.0;
        (permille / 1000.0 * rated).min(self.p.peak_current_a)
    }

    fn current_command(&mut self, fraction: f64, dt: f64) -> f64 {
        let state = self.sm.state();
        if self.safe_torque_off || !state.is_enabled() {
            return 0.0;
        }
        let i_max = self.current_limit();
        let tau_max = i_max * self.p.torque_per_amp;
        let (p, v) = (self.encoder_position(), self.velocity);
        let tau = if state == State::QuickStopActive {
            let (pr, vr, done) = self
                .servo
                .quick_stop_step(self.p.quick_stop_deceleration, dt);
            if done {
                self.sm.quick_stop_finished();
                return 0.0;
            }
            self.servo.torque(pr, vr, p, v, dt, tau_max)
        } else {
            match self.mode() {
                MODE_CSP => {
                    let (pr, vr) = self.servo.setpoint(fraction);
                    self.last_setpoint = (pr, vr);
                    // 0x60B2 torque offset: feed-forward added to the loop's output.
                    let offset = self.motor_torque_nm(od::TORQUE_OFFSET) / self.p.torque_constant
                        * self.p.torque_per_amp;
                    let ff = offset.clamp(-tau_max, tau_max);
                    let pid = self.servo.torque(pr, vr, p, v, dt, tau_max - ff.abs());
                    (pid + ff).clamp(-tau_max, tau_max)
                }
                MODE_CST => {
                    let motor_nm = self.motor_torque_nm(od::TARGET_TORQUE);
                    return (motor_nm / self.p.torque_constant).clamp(-i_max, i_max);
                }
                _ => 0.0,
            }
        };
        tau / self.p.torque_per_amp
    }

    /// The torque object in `slot` (per-mille of the rated torque 0x6076) [motor Nm].
    fn motor_torque_nm(&self, slot: usize) -> f64 {
        f64::from(self.od.i32(slot)) * f64::from(self.od.raw(od::RATED_TORQUE)) * 1e-6
    }

    fn sample(&mut self) {
        self.refresh_statusword();
        let clamp_i32 = |x: i64| x.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32;
        let clamp_i16 = |x: f64| x.round().clamp(f64::from(i16::MIN), f64::from(i16::MAX)) as i32;
        self.od
            .set_i32(od::POSITION_ACTUAL, clamp_i32(self.encoder_counts));
        self.od.set_i32(
            od::VELOCITY_ACTUAL,
            clamp_i32((self.velocity * self.p.counts_per_rad).round() as i64),
        );
        let rated_a = f64::from(self.od.raw(od::RATED_CURRENT)) / 1000.0;
        let rated_nm = f64::from(self.od.raw(od::RATED_TORQUE)) / 1000.0;
        self.od.set_i32(
            od::CURRENT_ACTUAL,
            clamp_i16(self.current_a / rated_a * 1000.0),
        );
        self.od.set_i32(
            od::TORQUE_ACTUAL,
            clamp_i16(self.current_a * self.p.torque_constant / rated_nm * 1000.0),
        );
    }

    fn refresh_statusword(&mut self) {
        let mode = self.mode();
        let inputs = StatusInputs {
            safe_torque_off: self.safe_torque_off,
            light_barrier: self
                .p
                .light_barrier_rad
                .is_some_and(|lb| self.joint_position > lb),
            following: mode == MODE_CSP || mode == MODE_CST,
        };
        self.od
            .set_raw(od::STATUSWORD, u32::from(self.sm.statusword(inputs)));
    }

    fn emit_events(&mut self, out: &mut dyn FrameSink) {
        if self.nmt == NmtState::Operational {
            self.refresh_statusword();
            for f in self
                .pdo
                .event_tx(&self.od, self.time_ns)
                .into_iter()
                .flatten()
            {
                out.emit(f);
            }
        }
    }

    fn emit_emcy(&self, code: u16, register: u8, out: &mut dyn FrameSink) {
        if self.nmt.emcy_allowed() {
            let mut data = [0u8; 8];
            data[..2].copy_from_slice(&code.to_le_bytes());
            data[2] = register;
            out.emit(Frame {
                id: EMCY_BASE + u16::from(self.p.node_id),
                len: 8,
                data,
            });
        }
    }

    fn record_fault(&mut self, (code, register): (u16, u8), out: &mut dyn FrameSink) {
        self.od.set_raw(od::ERROR_CODE, u32::from(code));
        self.od.set_raw(od::ERROR_REGISTER, u32::from(register));
        self.emit_emcy(code, register, out);
    }

    fn raise_fault(&mut self, emcy: (u16, u8), out: &mut dyn FrameSink) {
        let t = self.sm.fault();
        if t.is_some() {
            self.record_fault(emcy, out);
        }
        self.on_transition(t, out);
    }

    /// Entry actions of the CiA 402 states.
    fn on_transition(&mut self, t: Transition, out: &mut dyn FrameSink) {
        let Some((from, to)) = t else { return };
        match to {
            State::OperationEnabled => self.start_mode(),
            State::QuickStopActive => {
                let (p, v) = if self.mode() == MODE_CSP {
                    self.last_setpoint
                } else {
                    (self.encoder_position(), self.velocity)
                };
                self.servo.start_quick_stop(p, v);
            }
            State::SwitchOnDisabled if from == State::Fault => {
                self.od.set_raw(od::ERROR_CODE, 0);
                self.od.set_raw(od::ERROR_REGISTER, 0);
                self.emit_emcy(0x0000, 0x00, out);
            }
            _ => {}
        }
        if !to.is_enabled() {
            self.current_a = 0.0;
        }
    }

    /// Entering OPERATION ENABLED or changing the mode while enabled: in CSP the target becomes
    /// the actual position (no jump); in CST the position loop's integral is cleared.
    fn start_mode(&mut self) {
        match self.mode() {
            MODE_CSP => {
                self.od.set_i32(
                    od::TARGET_POSITION,
                    self.encoder_counts
                        .clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32,
                );
                let p = self.encoder_position();
                self.servo.hold(p);
                self.last_setpoint = (p, 0.0);
            }
            _ => self.servo.reset_integral(),
        }
    }

    fn mode_written(&mut self) {
        let mode = self.od.raw(od::MODES_OF_OPERATION);
        if mode != self.od.raw(od::MODES_DISPLAY) {
            self.od.set_raw(od::MODES_DISPLAY, mode);
            if self.sm.state() == State::OperationEnabled {
                self.start_mode();
            }
        }
    }

    /// Apply a received PDO: store every value, then act on the mode and the controlword (so
    /// that a target in the same PDO as the enabling controlword is replaced by the actual
    /// position).
    fn apply_pdo(&mut self, w: PdoWrites, out: &mut dyn FrameSink) {
        let prev_cw = self.od.raw(od::CONTROLWORD) as u16;
        let mut controlword = None;
        let mut mode = false;
        for (slot, raw) in w.iter() {
            match slot {
                od::MODES_OF_OPERATION if !valid_mode(raw) => {}
                od::MODES_OF_OPERATION => {
                    self.od.set_raw(slot, raw);
                    mode = true;
                }
                od::MAX_CURRENT => self.od.set_raw(
                    slot,
                    raw.min(u32::from(self.p.od_defaults.peak_current_permille)),
                ),
                od::CONTROLWORD => {
                    self.od.set_raw(slot, raw);
                    controlword = Some(raw as u16);
                }
                _ => self.od.set_raw(slot, raw),
            }
        }
        if mode {
            self.mode_written();
        }
        if let Some(cw) = controlword {
            let was = self.sm.state();
            let t = self.sm.write_controlword(cw, !self.safe_torque_off);
            // A fault-reset edge while OPERATION ENABLED (ignored by the state machine)
            // restarts the CSP loop where the joint stands: a new hold target, the integral
            // cleared (the MCM drive profile; see `docs/drive-profile.md`).
            let edge = cw & 0x80 != 0 && prev_cw & 0x80 == 0;
            if edge && t.is_none() && was == State::OperationEnabled && self.mode() == MODE_CSP {
                self.start_mode();
                self.counters.loop_restarts += 1;
            }
            self.on_transition(t, out);
        }
    }
}

fn valid_mode(raw: u32) -> bool {
    matches!(raw as u8 as i8, 0 | MODE_CSP | MODE_CST)
}

mod objects;

#[cfg(test)]
mod tests;
