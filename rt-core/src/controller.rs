//! The controller: the operating modes, the commands, and what the drives are asked to do.
//!
//! Runs inside the cycle. A deterministic function of its inputs: [`Controller::step`] takes
//! the controller time, the frames received from the bus and the commands received, and
//! produces the frames to send, the replies and the state (kept in the state sample, whose
//! reply ring carries the replies). No allocation, no locks, no I/O, no logging.
//!
//! Modes implemented so far: `OFF` (drives disabled, the start-up mode), `HOLD` (every axis
//! position-controlled where it was when HOLD began) and `ERROR` (entered when a drive is lost
//! or faults; axes held where the drives still answer; `hold` clears it). The other commands of
//! the manual are recognised and answered with `not_available` until they are implemented.

use crate::canopen::{AxisFeedback, DriveRequest, FrameBuf, Master, MasterEvent};
use crate::request::{self, Request};
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode, RejectCode, ReplyStatus};
use mcm_shared::sample::{
    AXIS_CALIBRATED, AXIS_ENABLED, AXIS_FAULT, AXIS_ONLINE, CommandSample, ErrorRecord, Reply,
    STATE_ALL_CALIBRATED, STATE_ESTOP, StateSample,
};

/// How long `hold` waits at least for every drive to reach Operation Enabled.
const ENABLE_TIMEOUT_NS: u64 = 2_000_000_000;

/// A `hold` that waits for the drives to be enabled.
#[derive(Debug, Clone, Copy)]
struct PendingHold {
    client_id: u64,
    request_id: u64,
    deadline_ns: u64,
}

/// The controller of one arm.
pub struct Controller {
    master: Master,
    period_s: f64,
    simulated: bool,
    max_current: [f64; NUM_AXES],
    mode: Mode,
    /// Raw (encoder-frame) position each axis holds in HOLD/ERROR [rad].
    hold_target: [f64; NUM_AXES],
    /// Calibration offset per axis: joint angle = raw position - offset [rad].
    calibration: [Option<f64>; NUM_AXES],
    pending_hold: Option<PendingHold>,
    /// Drives the master reported lost, missing or failed to configure (until it reports them
    /// configured or recovered).
    lost: [bool; NUM_AXES],
    /// How long `hold` waits for the drives: covers a drive still booting.
    enable_timeout_ns: u64,
    requests: [DriveRequest; NUM_AXES],
    prev_velocity: [f64; NUM_AXES],
    acceleration: [f64; NUM_AXES],
    state: StateSample,
    cycle: u64,
}

impl Controller {
    /// Build the controller; `simulated` says whether the bus is the simulated robot.
    pub fn new(cfg: &RobotConfig, master: Master, simulated: bool) -> Controller {
        let mut state = StateSample::default();
        if simulated {
            state.flags |= mcm_shared::sample::STATE_SIMULATED;
        }
        Controller {
            master,
            period_s: cfg.cycle_period_s(),
            simulated,
            max_current: core::array::from_fn(|i| cfg.axes[i].max_current_a),
            mode: Mode::Off,
            hold_target: [0.0; NUM_AXES],
            calibration: [None; NUM_AXES],
            pending_hold: None,
            lost: [false; NUM_AXES],
            enable_timeout_ns: ENABLE_TIMEOUT_NS
                .max(u64::from(cfg.bus.boot_timeout_ms) * 1_000_000),
            requests: [DriveRequest::Disable; NUM_AXES],
            prev_velocity: [0.0; NUM_AXES],
            acceleration: [0.0; NUM_AXES],
            state,
            cycle: 0,
        }
    }

    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The state sample as of the last step (replies included).
    pub fn state(&self) -> &StateSample {
        &self.state
    }

    /// The state sample, for the edge to add timing and simulation truth before publishing.
    pub fn state_mut(&mut self) -> &mut StateSample {
        &mut self.state
    }

    /// The drive feedback of the last step.
    pub fn feedback(&self) -> &[AxisFeedback; NUM_AXES] {
        self.master.feedback()
    }

    /// Append a reply to the state's reply ring (also used by the edge for `sim` commands).
    pub fn push_reply(&mut self, reply: Reply) {
        self.state.push_reply(reply);
    }

    /// One cycle: `now_ns` is controller time (cycle index x period); `rx` the frames received
    /// since the last cycle; `commands` the commands received. Frames to send are appended to
    /// `tx`, SYNC last.
    pub fn step(
        &mut self,
        now_ns: u64,
        rx: &[crate::bus::Frame],
        commands: &[CommandSample],
        tx: &mut FrameBuf,
    ) {
        self.cycle += 1;
        for f in rx {
            self.master.handle_frame(now_ns, f);
        }
        while let Some(ev) = self.master.poll_event() {
            self.on_event(ev);
        }
        for c in commands {
            self.on_command(now_ns, c);
        }
        self.update_pending_hold(now_ns);
        self.plan_requests();
        self.master
            .cycle(now_ns, &self.requests, &self.max_current, tx);
        self.fill_state(now_ns);
    }

    fn reply(
        &mut self,
        c: &CommandSample,
        status: ReplyStatus,
        code: RejectCode,
        axis: u32,
        values: &[f64],
    ) {
        let mut r = Reply {
            client_id: c.client_id,
            request_id: c.request_id,
            kind: c.kind,
            status: status.to_wire(),
            code: code.to_wire(),
            axis,
            ..Reply::default()
        };
        let n = values.len().min(r.values.len());
        r.values[..n].copy_from_slice(&values[..n]);
        self.state.push_reply(r);
    }

    fn ok(&mut self, c: &CommandSample, values: &[f64]) {
        self.reply(c, ReplyStatus::Ok, RejectCode::None, 0, values);
    }

    fn reject(&mut self, c: &CommandSample, code: RejectCode, axis: u32, values: &[f64]) {
        self.reply(c, ReplyStatus::Rejected, code, axis, values);
    }

    fn on_command(&mut self, now_ns: u64, c: &CommandSample) {
        let req = match request::decode(c) {
            Ok(r) => r,
            Err(e) => return self.reject(c, e.code, e.axis, &e.values),
        };
        match req {
            Request::Status => self.ok(c, &[]),
            Request::Info => {
                let sim = if self.simulated { 1.0 } else { 0.0 };
                self.ok(c, &[NUM_AXES as f64, self.period_s, sim]);
            }
            Request::Hold => self.on_hold(now_ns, c),
            Request::Sim(_) => {
                // Fault injection is handled at the bus edge; reaching here means there is no
                // simulated robot.
                self.reject(c, RejectCode::NotSimulated, 0, &[]);
            }
            Request::Calibrate { .. }
            | Request::Release
            | Request::TorqueControl { .. }
            | Request::Pvt { .. }
            | Request::MoveAxis { .. }
            | Request::MoveAll { .. }
            | Request::PvtPoints { .. }
            | Request::SetTorques { .. } => self.reject(c, RejectCode::NotAvailable, 0, &[]),
        }
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

    fn on_hold(&mut self, now_ns: u64, c: &CommandSample) {
        match self.mode {
            Mode::Hold => self.ok(c, &[]),
            Mode::Off | Mode::Error => {
                if let Some((code, axis)) = self.enable_blocker() {
                    return self.reject(c, code, axis, &[]);
                }
                if let Some(prev) = self.pending_hold.take() {
                    let superseded = CommandSample {
                        client_id: prev.client_id,
                        request_id: prev.request_id,
                        kind: CommandKind::Hold.to_wire(),
                        ..*c
                    };
                    self.reply(
                        &superseded,
                        ReplyStatus::Failed,
                        RejectCode::Aborted,
                        0,
                        &[],
                    );
                }
                self.master.reset_faults();
                self.latch_hold_targets();
                self.pending_hold = Some(PendingHold {
                    client_id: c.client_id,
                    request_id: c.request_id,
                    deadline_ns: now_ns + self.enable_timeout_ns,
                });
            }
            _ => {
                // The motion modes come with their own issue; until then they cannot be entered.
                self.latch_hold_targets();
                self.mode = Mode::Hold;
                self.ok(c, &[]);
            }
        }
    }

    fn latch_hold_targets(&mut self) {
        let fb = self.master.feedback();
        self.hold_target = core::array::from_fn(|i| fb[i].position_rad);
    }

    fn update_pending_hold(&mut self, now_ns: u64) {
        let Some(p) = self.pending_hold else { return };
        let fb = self.master.feedback();
        let done = |c: &mut Self, status, code, axis| {
            let s = CommandSample {
                client_id: p.client_id,
                request_id: p.request_id,
                kind: CommandKind::Hold.to_wire(),
                ..CommandSample::default()
            };
            c.pending_hold = None;
            c.reply(&s, status, code, axis, &[]);
        };
        if fb.iter().all(|f| f.enabled) {
            self.mode = Mode::Hold;
            done(self, ReplyStatus::Ok, RejectCode::None, 0);
        } else if let Some((code, axis)) = self.enable_blocker() {
            done(self, ReplyStatus::Failed, code, axis);
        } else if now_ns >= p.deadline_ns {
            let axis = fb
                .iter()
                .position(|f| !f.enabled)
                .map_or(0, |i| i as u32 + 1);
            done(self, ReplyStatus::Failed, RejectCode::DriveFault, axis);
        }
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
                    self.trip(
                        RejectCode::DriveFault,
                        axis,
                        [f64::from(emcy.code), 0.0, 0.0, 0.0],
                    );
                }
            }
            MasterEvent::Fault { axis, code } => {
                self.trip(
                    RejectCode::DriveFault,
                    axis,
                    [f64::from(code), 0.0, 0.0, 0.0],
                );
            }
            MasterEvent::ConfigFailed { axis, .. } => {
                self.lost[axis] = true;
                self.trip(RejectCode::DriveDisconnected, axis, [0.0; 4]);
            }
            MasterEvent::Booted { axis } => {
                // A drive that boots lost its encoder reference: calibration is gone.
                self.calibration[axis] = None;
                if self.mode != Mode::Off {
                    self.trip(RejectCode::DriveDisconnected, axis, [0.0; 4]);
                }
            }
        }
    }

    /// A safety check or drive error: mode ERROR (from any mode but OFF, where nothing moves
    /// and the error is only reported), and one spontaneous error record.
    fn trip(&mut self, code: RejectCode, axis0: usize, values: [f64; 4]) {
        if self.mode != Mode::Off {
            if self.mode != Mode::Error {
                self.latch_hold_targets();
            }
            self.mode = Mode::Error;
        }
        let e = &mut self.state.last_error;
        *e = ErrorRecord {
            seq: e.seq + 1,
            cycle: self.cycle,
            code: code.to_wire(),
            axis: axis0 as u32 + 1,
            values,
        };
    }

    fn plan_requests(&mut self) {
        let fb = self.master.feedback();
        for (i, f) in fb.iter().enumerate() {
            self.requests[i] = match self.mode {
                Mode::Off if self.pending_hold.is_none() => DriveRequest::Disable,
                Mode::Error if self.pending_hold.is_none() => {
                    if f.online && !f.state.is_fault() && f.enabled {
                        DriveRequest::Position {
                            position_rad: self.hold_target[i],
                        }
                    } else {
                        DriveRequest::Disable
                    }
                }
                _ => DriveRequest::Position {
                    position_rad: self.hold_target[i],
                },
            };
        }
    }

    fn fill_state(&mut self, now_ns: u64) {
        let fb = *self.master.feedback();
        let s = &mut self.state;
        s.seq = self.cycle;
        s.t_ns = now_ns;
        s.mode = self.mode.to_wire();
        let mut flags = s.flags & !(STATE_ESTOP | STATE_ALL_CALIBRATED);
        if fb.iter().any(|f| f.estop) {
            flags |= STATE_ESTOP;
        }
        if self.calibration.iter().all(Option::is_some) {
            flags |= STATE_ALL_CALIBRATED;
        }
        s.flags = flags;
        let holding = matches!(self.mode, Mode::Hold | Mode::Error) || self.pending_hold.is_some();
        for (i, f) in fb.iter().enumerate() {
            let offset = self.calibration[i].unwrap_or(0.0);
            let measured = (f.position_rad - offset).to_degrees();
            let commanded = if holding {
                (self.hold_target[i] - offset).to_degrees()
            } else {
                measured
            };
            let v = f.velocity_rad_s;
            let a = (v - self.prev_velocity[i]) / self.period_s;
            self.prev_velocity[i] = v;
            // A light low-pass: differentiated velocity is noisy.
            self.acceleration[i] += 0.2 * (a - self.acceleration[i]);
            s.position[i] = measured;
            s.measured_position[i] = measured;
            s.velocity[i] = v.to_degrees();
            s.acceleration[i] = self.acceleration[i].to_degrees();
            s.current[i] = f.current_a;
            s.commanded_position[i] = commanded;
            s.following_error[i] = commanded - measured;
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
            if self.calibration[i].is_some() {
                af |= AXIS_CALIBRATED;
            }
            s.axis_flags[i] = af;
        }
    }
}
