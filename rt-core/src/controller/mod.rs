//! The controller: operating modes, commands, reference generation, and what each drive is
//! asked to do.
//!
//! Runs inside the cycle. A deterministic function of its inputs: [`Controller::step`] takes
//! the controller time, the frames received from the bus and the commands received, and
//! produces the frames to send and a view of the cycle in SI units ([`CycleView`], with the
//! cycle's replies), from which [`crate::publish`] composes the published state. No
//! allocation, no locks, no I/O, no logging.
//!
//! Frames of reference: the drives work in raw encoder angles; the controller works in joint
//! angles, `joint = raw - offset`, where an axis's offset is found by calibration (0 until
//! then). The reference sent in a cycle is the one for the end of that cycle: the drives apply
//! it at the SYNC that closes the cycle and reach it one period later.
//!
//! The files of this module: `mod.rs` (the cycle, enabling the drives), `state.rs` (the operating
//! state: one enum carrying each mode's data), `commands.rs` (what each command does), `exits.rs`
//! (the one path by which a mode ends before its time: `hold`, a gone owner, a shutdown, a timeout,
//! a trip), `moves.rs` (`move_axis`/`move_all`, re-planned during motion), `calibrate.rs` (a
//! calibration's searches, and keeping the previous calibration when one does not complete),
//! `motion.rs` (the per-cycle reference of each motion), `ownership.rs` (which client controls the
//! arm's motion), `trips.rs` (drive events and safety trips), `view.rs` (what a cycle reports),
//! `shutdown_sequence.rs` (the controlled stop and disable when `mcm-rt` is asked to stop),
//! `velocity.rs` (VELOCITY_CONTROL, its ramp and the joint velocities of a TCP velocity), `release.rs` (RELEASE's soft speed limit),
//! `tool.rs` (the active tool, `set_tool`), `linear.rs` (`move_linear`, its line planned beside
//! the cycle).

mod calibrate;
mod calibrate_relax;
mod commands;
mod exits;
mod identify_payload;
mod linear;
mod motion;
mod moves;
mod overload;
mod ownership;
pub mod planted;
pub mod release;
mod shutdown_sequence;
mod state;
mod tool;
mod trips;
pub mod velocity;
mod view;

use crate::calibration::AxisSettings;
use crate::canopen::{AxisFeedback, DriveRequest, FrameBuf, Master};
use crate::cartesian::Cartesian;
use crate::params::JointParams;
use crate::pvt::PvtStream;
use crate::safety::{CycleChecks, I2t, SafetyParams};
use crate::trajectory::JointSample;
use mcm_dynamics::ArmModel;
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Axis, Request};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::Mode;
use mcm_shared::reply::{self, Done, Outcome, Reason, Response};
use mcm_shared::sample::{CommandSample, Reply};
pub use motion::QUICK_STOP_FACTOR;
pub use overload::OVERLOAD_S;
pub use shutdown_sequence::{
    SHUTDOWN_HOLD_NS, SHUTDOWN_MIN_BOUND_NS, ShutdownPhase, ShutdownResult, ShutdownStatus,
    TimedOutPhase,
};
use state::{After, Before, Caller, State};
pub use view::{AxisView, CycleView, Outbox};

/// How long a mode change waits at least for every drive to reach Operation Enabled.
const ENABLE_TIMEOUT_NS: u64 = 2_000_000_000;
/// Share of the model's friction that RELEASE and TORQUE_CONTROL compensate. Less than all of
/// it, so that an arm let go comes to rest instead of drifting on.
pub const FRICTION_COMPENSATION: f64 = 0.7;
/// Extra damping in RELEASE, as a multiple of each joint's viscous friction: an arm pushed and
/// let go comes to rest within a fraction of a second.
pub const RELEASE_DAMPING: f64 = 1.0;

/// The controller of one arm.
pub struct Controller {
    master: Master,
    p: JointParams,
    model: ArmModel,
    /// The kinematics with the active tool's TCP (`tool.rs` keeps them with the model's tool):
    /// the published TCP state and VELOCITY_CONTROL's TCP velocity.
    cartesian: Cartesian,
    i2t: I2t,
    safety: SafetyParams,
    /// The per-cycle safety checks with their parameters (`trips.rs` runs them).
    checks: CycleChecks,
    /// RELEASE's soft speed limit (`release.rs`).
    release: release::ReleaseParams,
    /// The torque feed-forward sent to each drive's position loop [Nm] (`motion.rs`).
    feed_forward: [f64; NUM_AXES],
    /// The emergency stop input of the last cycle (a press is reported once, on its edge).
    estop_seen: bool,
    /// An error was reported and not yet cleared by a successful `hold`: later trips of the
    /// same incident are not reported again. Not part of [`State`]: an incident outlives the
    /// mode it tripped in (a trip in OFF stays reported through a calibration until a `hold`
    /// succeeds).
    incident_reported: bool,
    /// Calibration settings per axis: `[reverse][force_mechanical_stop]`.
    cal_settings: [[[AxisSettings; 2]; 2]; NUM_AXES],
    state: State,
    /// Joint = raw - offset; `None` until calibrated.
    offsets: [Option<f64>; NUM_AXES],
    /// The commanded reference of this cycle (joint frame).
    cmd: JointSample,
    /// The commanded positions of the last two cycles: `[k-1, k-2]`. The position measured in
    /// cycle k was sampled when the drives were reaching the command of cycle k-2.
    cmd_hist: [[f64; NUM_AXES]; 2],
    /// Joint torques commanded in the torque modes.
    cmd_torque: [f64; NUM_AXES],
    stream: PvtStream,
    /// Drives the master reported lost, missing or failed (until configured or recovered).
    lost: [bool; NUM_AXES],
    enable_timeout_ns: u64,
    requests: [DriveRequest; NUM_AXES],
    current_limit: [f64; NUM_AXES],
    /// The relax of the axes whose calibration search ended without success (`calibrate_relax.rs`,
    /// [`calibrate_relax::SearchRelax`]). Not part of [`State`]: the relax outlives the ERROR of a
    /// failed search, the enabling a `hold` starts from there and the arrival in HOLD.
    search_relax: calibrate_relax::SearchRelax,
    /// The overload check (`overload.rs`): an axis derated by i2t that cannot hold its load.
    overload: overload::Overload,
    prev_velocity: [f64; NUM_AXES],
    acceleration: [f64; NUM_AXES],
    view: CycleView,
    cycle: u64,
    now_ns: u64,
    /// The client that controls the arm's motion (0: nobody); see `ownership.rs`.
    owner: u64,
    /// The shutdown, once `mcm-rt` was asked to stop (`shutdown_sequence.rs`).
    shutdown: Option<ShutdownStatus>,
    /// Bugs planted by the simulation tester (`planted.rs`): none in `mcm-rt`.
    planted: planted::Planted,
    /// A line to plan, posted for the cycle to hand to the planner (`linear.rs`).
    line_request: Option<crate::line_planner::LineRequest>,
    /// The plan of the line that runs, or ran last (about 13 kB, kept here rather than in
    /// [`State`], which is copied every cycle).
    line: Option<mcm_kinematics::LinePlan>,
    /// The id of the last line requested.
    line_ids: u64,
}

impl Controller {
    /// Build the controller of the arm `cfg` describes, over the CANopen `master`, with the
    /// arm's kinematics with the configured tool's TCP (`Cartesian::from_config`).
    pub fn new(cfg: &RobotConfig, master: Master, cartesian: Cartesian) -> Controller {
        let p = JointParams::from_config(cfg);
        let stream = PvtStream::new();
        let view = CycleView {
            pvt_capacity: u32::try_from(stream.capacity()).unwrap_or(u32::MAX),
            ..CycleView::default()
        };
        Controller {
            master,
            model: ArmModel::from_config(cfg),
            cartesian,
            i2t: I2t::new(&SafetyParams::from_config(cfg)),
            safety: SafetyParams::from_config(cfg),
            checks: CycleChecks::from_config(cfg),
            release: release::ReleaseParams::from_config(cfg),
            feed_forward: [0.0; NUM_AXES],
            estop_seen: false,
            incident_reported: false,
            cal_settings: core::array::from_fn(|axis| {
                core::array::from_fn(|rev| {
                    core::array::from_fn(|force| {
                        AxisSettings::from_config(cfg, axis, rev == 1, force == 1)
                    })
                })
            }),
            state: State::Off,
            offsets: [None; NUM_AXES],
            cmd: JointSample::default(),
            cmd_hist: [[0.0; NUM_AXES]; 2],
            cmd_torque: [0.0; NUM_AXES],
            stream,
            lost: [false; NUM_AXES],
            enable_timeout_ns: ENABLE_TIMEOUT_NS
                .max(u64::from(cfg.bus.boot_timeout_ms) * 1_000_000),
            requests: [DriveRequest::Disable; NUM_AXES],
            current_limit: p.max_current,
            search_relax: calibrate_relax::SearchRelax::NONE,
            overload: overload::Overload::default(),
            prev_velocity: [0.0; NUM_AXES],
            acceleration: [0.0; NUM_AXES],
            p,
            view,
            cycle: 0,
            now_ns: 0,
            owner: 0,
            shutdown: None,
            planted: planted::Planted::default(),
            line_request: None,
            line: None,
            line_ids: 0,
        }
    }

    pub fn mode(&self) -> Mode {
        self.state.mode()
    }

    /// The view of the last step (replies included), in SI units.
    pub fn view(&self) -> &CycleView {
        &self.view
    }

    /// The drive feedback of the last step.
    pub fn feedback(&self) -> &[AxisFeedback; NUM_AXES] {
        self.master.feedback()
    }

    /// What the last step asked of each drive.
    pub fn requests(&self) -> &[DriveRequest; NUM_AXES] {
        &self.requests
    }

    /// Calibration offsets (joint = raw - offset) [rad].
    pub fn offsets(&self) -> [Option<f64>; NUM_AXES] {
        self.offsets
    }

    /// Start a new cycle's outbox: the replies of the last cycle were published. Called by
    /// [`crate::cycle::Cycle::receive`], before the simulator's edge answers `sim` commands.
    pub fn begin_cycle(&mut self) {
        self.view.replies.clear();
    }

    /// The bus errors the cycle counted since start (frames not sent or not received), for the
    /// view ([`CycleView::bus`]).
    pub fn note_bus_errors(&mut self, bus_errors: u64) {
        self.view.bus.bus_errors = bus_errors;
    }

    /// Add a reply to this cycle's outbox (also used by the simulator's edge,
    /// [`crate::sim_edge`], for `sim` commands).
    pub fn answer(&mut self, reply: Reply) {
        self.view.replies.push(reply);
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
            match Request::decode(c) {
                Ok(req) => {
                    let caller = Caller {
                        client_id: c.client_id,
                        request_id: c.request_id,
                        kind: req.kind(),
                    };
                    if !self.refused_for_shutdown(caller, &req)
                        && let ownership::Gate::Pass = self.gate(caller, &req)
                    {
                        self.on_request(caller, req);
                    }
                }
                Err(e) => self.answer(reply::refuse_undecodable(c, &e)),
            }
        }
        self.advance_shutdown();
        self.update_enabling();
        self.check_safety();
        self.check_overload();
        self.cmd_hist = [self.cmd.position, self.cmd_hist[0]];
        self.advance_motion();
        self.update_i2t();
        self.master
            .cycle(now_ns, &self.requests, &self.current_limit, tx);
        self.fill_view();
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

    /// Answer `to` with `outcome`.
    fn reply(&mut self, to: Caller, outcome: Outcome) {
        let r = Response {
            client_id: to.client_id,
            request_id: to.request_id,
            kind: to.kind,
            outcome,
        };
        self.answer(r.encode());
    }

    fn done(&mut self, to: Caller, done: Done) {
        self.reply(to, Outcome::Done(done));
    }

    fn refuse(&mut self, to: Caller, reason: Reason) {
        self.reply(to, Outcome::Refused(reason));
    }

    fn fail(&mut self, to: Caller, reason: Reason) {
        self.reply(to, Outcome::Failed(reason));
    }

    /// A reason the drives cannot be enabled now: emergency stop, a drive the master gave
    /// up on (a drive still booting is waited for), or an arm powered off onto its brakes whose
    /// motor is still derated (`overload.rs`).
    fn enable_blocker(&self) -> Option<Reason> {
        let fb = self.master.feedback();
        if fb.iter().any(|f| f.estop) {
            return Some(Reason::EmergencyStop);
        }
        if let Some(hot) = self.overload_blocker() {
            return Some(hot);
        }
        self.lost
            .iter()
            .position(|l| *l)
            .map(|i| Reason::DriveDisconnected {
                axis: Axis::ALL[i],
                also: 0,
            })
    }

    /// Start enabling every drive, holding where it is; an enabling already under way is
    /// superseded (its caller told so).
    fn begin_enabling(&mut self, caller: Caller, then: After) {
        let from = match self.state {
            State::Enabling {
                caller: prev, from, ..
            } => {
                self.fail(prev, Reason::Aborted);
                from
            }
            State::Error { .. } => Before::Error,
            _ => Before::Off,
        };
        self.master.reset_faults();
        self.overload.powered_off = false;
        self.hold_here();
        self.state = State::Enabling {
            caller,
            deadline_ns: self.now_ns + self.enable_timeout_ns,
            from,
            then,
        };
    }

    fn update_enabling(&mut self) {
        let State::Enabling {
            caller,
            deadline_ns,
            from,
            then,
        } = self.state
        else {
            return;
        };
        let fb = self.master.feedback();
        if fb.iter().all(|f| f.enabled) {
            match then {
                After::Hold => {
                    self.incident_reported = false;
                    self.hold_here();
                    self.arrive_in_hold(caller);
                }
                After::Calibrate(settings) => self.start_calibration(caller, settings),
                After::HoldAborted => {
                    self.incident_reported = false;
                    self.hold_here();
                    self.state = State::Hold { stop: None };
                    self.fail(caller, Reason::Aborted);
                }
            }
            return;
        }
        let failed = self.enable_blocker().or_else(|| {
            let axis = fb.iter().position(|f| !f.enabled).map(|i| Axis::ALL[i]);
            (self.now_ns >= deadline_ns).then_some(Reason::DriveFault { axis, code: 0 })
        });
        if let Some(reason) = failed {
            self.state = self.enabling_failed(caller, from, reason);
        }
    }

    /// What `caller` waited for (an enabling for `hold`, a calibration) completed: HOLD, at
    /// rest, and its reply.
    pub(super) fn arrive_in_hold(&mut self, caller: Caller) {
        self.state = State::Hold { stop: None };
        self.done(caller, Done::Ack);
    }

    /// Command every axis at its measured position, at rest (the caller sets the state).
    fn hold_here(&mut self) {
        self.cmd = JointSample {
            position: self.measured(),
            ..JointSample::default()
        };
        self.cmd_hist = [self.cmd.position; 2];
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

    /// This cycle's view, in SI units (the replies are already in its outbox).
    fn fill_view(&mut self) {
        let fb = *self.master.feedback();
        let measured = self.measured();
        let mode = self.mode();
        let v = &mut self.view;
        v.cycle = self.cycle;
        v.mode = mode;
        v.estop = fb.iter().any(|f| f.estop);
        v.all_calibrated = self.offsets.iter().all(Option::is_some);
        v.pvt_starved = matches!(self.state, State::Pvt { starved: true, .. });
        v.pvt_queued = u32::try_from(self.stream.queued()).unwrap_or(u32::MAX);
        v.owner_client_id = self.owner;
        v.tool = *self.model.tool();
        v.bus.bad_frames = self.master.bad_frames();
        v.bus.frames_dropped = self.master.frames_dropped();
        v.bus.events_dropped = self.master.events_dropped();
        let level = self.i2t.level();
        let derated = self.i2t.derated();
        for (i, f) in fb.iter().enumerate() {
            let vel = f.velocity_rad_s;
            let a = (vel - self.prev_velocity[i]) / self.p.period;
            self.prev_velocity[i] = vel;
            // A light low-pass: differentiated velocity is noisy.
            self.acceleration[i] += 0.2 * (a - self.acceleration[i]);
            let (position, velocity, acceleration, current) = match mode {
                Mode::Pvt => (
                    self.cmd.position[i],
                    self.cmd.velocity[i],
                    self.cmd.acceleration[i],
                    f.current_a,
                ),
                Mode::Release | Mode::TorqueControl => (
                    measured[i],
                    vel,
                    self.acceleration[i],
                    self.cmd_torque[i] / self.p.torque_per_amp[i],
                ),
                _ => (measured[i], vel, self.acceleration[i], f.current_a),
            };
            v.axes[i] = AxisView {
                position,
                velocity,
                acceleration,
                current,
                measured_position: measured[i],
                commanded_position: self.cmd.position[i],
                following_error: self.cmd_hist[1][i] - measured[i],
                i2t: level[i],
                online: f.online,
                enabled: f.enabled,
                fault: f.state.is_fault(),
                calibrated: self.offsets[i].is_some(),
                derated: derated[i],
            };
        }
    }
}

// Scenario tests on the whole simulated robot.
#[cfg(all(test, feature = "sim"))]
mod tests;
