//! The invariants checked after every cycle of a run. Each violation names the cycle, the
//! axis (1-based, where one is concerned) and the values.
//!
//! - every number of the published state is finite;
//! - the true joint angle never beyond the mechanical stops (the hard limits) by more than
//!   the stops' spring can give ([`STOP_PENETRATION_DEG`]);
//! - the true joint angle never beyond a software limit by more than [`LIMIT_OVERRUN_DEG`]
//!   while the controller is responsible for it: a calibrated axis (with a calibration no
//!   obstacle or push acted on, see below: the controller cannot know where such an axis is),
//!   powered in HOLD, PVT,
//!   VELOCITY_CONTROL, TORQUE_CONTROL or ERROR, with no push, obstacle, power cycle, emergency
//!   stop, silent drive or drive rebooting under way, that was inside its limits and at rest
//!   since (an axis that comes in from a motion the controller was not responsible for, a
//!   calibration search cut short, is owed its stop first);
//! - every command answered exactly once, with the kind it asked: within [`QUEUE_CYCLES`] of
//!   its sending, plus the drives' enabling for a `hold` or `calibrate` (which wait for it),
//!   and for a `calibrate` however long its calibration runs (the mode CALIBRATION); none
//!   left unanswered when the quiet phase has brought the arm back
//!   ([`Checker::left_unanswered`]; a run that does not get there ends with commands that
//!   may still be within their bound, which the per-cycle bound judged up to then);
//! - an OK to `pvt`, `release`, `torque_control`, `velocity_control` is published with its
//!   mode, and an OK to `hold` with HOLD (or ERROR: a trip in the same cycle; a `hold` also
//!   CALIBRATION when a `calibrate` served after it in the cycle started one), and an OK to
//!   `calibrate` (given when the calibration ends) with every axis it covered flagged
//!   calibrated, unless a later command of that cycle changed the mode again;
//! - a refusal says what was so, in the state published before the cycle or after it: the
//!   mode a `wrong_mode` names was the mode, the axis a `not_calibrated` names was not flagged
//!   calibrated, the emergency stop an `emergency_stop` names was pressed; and a motion command
//!   refused did not enter its mode (not judged where another command of the cycle changed
//!   the mode);
//! - only legal mode transitions: the motion modes entered from HOLD only, CALIBRATION from
//!   OFF or HOLD only, OFF never entered again once left; two in one cycle through HOLD (a
//!   `hold` answered OK, then the command entering the mode served after it) are legal;
//! - after a trip (the mode ERROR entered), every axis that was moving at standstill within its
//!   braking distance as the braking check computes it (`docs/safety.md`, "Braking distance":
//!   the speed times the reaction latency, plus `v^2 / (2 braking_efficiency a_max)`), from the
//!   fastest true speed of the cycles the measurement lags, plus the lag's own travel and
//!   [`STANDSTILL_SLACK_DEG`] (plus [`SEARCH_RELAX_DEG`] for an axis springing back out of
//!   the mechanical stop a search pressed it into); and within the time that takes plus [`STANDSTILL_SLACK_S`]
//!   ([`Stopping`]); judged while the mode stays ERROR (a client's `hold` commands the arm
//!   again) and not while a push, an obstacle, a power cycle, an emergency stop, a silent
//!   drive or a drive rebooting acts (the arm is not the controller's to stop then; while the
//!   SYNC is stuck, its drive's SYNC watchdog's time is added at the speed of the moment), nor
//!   while an axis whose calibration an obstacle or a push fooled is measured off the truth
//!   (the controller's picture of the arm, its gravity compensation included, is wrong);
//! - no axis flagged calibrated whose measured angle is further from the true angle than its
//!   calibration tolerance, plus the motion of the cycles the measurement may lag the truth
//!   ([`Checker::new`]: two, and the TPDOs the master may miss in a row, and while frames to
//!   the master are delayed, the [`DELAY_SYNCS`] they may be late); not judged for an axis
//!   whose drive is not online (the master lost it: its measured angle stands); not judged for an
//!   axis calibrated while an obstacle or a push acted during the calibration (a stop-based
//!   calibration cannot tell an obstacle or a hand from its stop) until it is calibrated again;
//! - with every axis calibrated, the TCP's state (`cartesian_state`) is the forward kinematics
//!   of the axis positions the same sample reports, and its velocity the Jacobian times the
//!   axis velocities it reports (1e-9 m, 1e-9 rad, [`tcp`]); absent before;
//! - no allocation in the cycle's work, and its work within `cycle.work_budget_us` of CPU time
//!   (measured on the thread's CPU clock, which a preemption does not advance; it includes the
//!   simulated drives' and physics' share, so the controller's own work is less; ten times
//!   that in a debug build, [`DEBUG_SLOWDOWN`]).

use crate::faults::Fault;
use crate::faulty_bus::MAX_DELAY_SYNCS as DELAY_SYNCS;
use mcm_rt_core::safety::SafetyParams;
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Axis, Request, Which};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode};
use mcm_shared::protocol::core_reply_within;
use mcm_shared::reply::{Outcome, Reason, Response};
use mcm_shared::sample::{
    AXIS_CALIBRATED, AXIS_ONLINE, CommandSample, Reply, STATE_ESTOP, StateSample,
};
use mcm_sim::SimBus;
use mcm_sim::drive::SYNC_LOSS_PERIODS;
use std::collections::{HashMap, VecDeque};

pub mod tcp;

/// How far the stops' spring may give [deg]. Not derived at run time; the P-Rob2's figures
/// (`deploy/prob2.toml`, the stops' `sim.stop_stiffness_nm_rad` 20 000 Nm/rad): pressed by
/// the largest torques (a motor's peak torque, 129.6 Nm on axes 1 to 3, a push of up to
/// [`PUSH_MAX_NM`](crate::faults::PUSH_MAX_NM), gravity up to 65 Nm on axis 2) a stop gives
/// up to 0.6 deg; hit at the overspeed limit (1.1 x 90 deg/s) with the arm stretched (up to
/// 4.6 kg m^2 on axes 1 and 2) it gives up to 1.5 deg more (undamped, `v·sqrt(I/k)`). 2 deg
/// is about their sum. A push on an unpowered axis is held to no speed limit and may go
/// deeper (`docs/findings.md`, "Open").
pub const STOP_PENETRATION_DEG: f64 = 2.0;
/// How far past a software limit the controller may let an axis go [deg].
pub const LIMIT_OVERRUN_DEG: f64 = 1.0;
/// How far an axis whose calibration search pressed it into its mechanical stop may spring
/// back out of it after a trip, beyond its braking distance [deg]: the band of the controller's
/// relax (`controller/calibrate_relax.rs`, `RELAX_BAND_RAD`).
pub const SEARCH_RELAX_DEG: f64 = 0.5;
/// Travel allowed after a trip beyond the braking distance [deg]: the drive's position loop
/// lags the stop's reference by up to the following error of the moment.
pub const STANDSTILL_SLACK_DEG: f64 = 0.5;
/// Time allowed after a trip beyond the stop's own duration [s]: the position loop settling.
pub const STANDSTILL_SLACK_S: f64 = 0.5;
/// How much more CPU time a cycle's work may take in a build with debug assertions (the
/// workspace's dev profile, `opt-level = 1`, which CI's tests run), whose code is several
/// times slower than the release build's the budget is meant for; 1 in a release build.
pub const DEBUG_SLOWDOWN: u64 = if cfg!(debug_assertions) { 10 } else { 1 };
/// An axis slower than this is at standstill [deg/s].
pub const STANDSTILL_DEG_S: f64 = 0.5;

/// An axis braking after a trip, watched until standstill.
#[derive(Debug, Clone, Copy)]
struct Stopping {
    /// The cycle of the trip.
    cycle: u64,
    /// The true angle at the trip [deg] and the direction of motion (+1 or -1).
    from_deg: f64,
    direction: f64,
    /// The speed the bound was computed from [deg/s].
    speed: f64,
    /// The travel allowed [deg], and the furthest travelled so far.
    allowed_deg: f64,
    travelled_deg: f64,
    /// The last cycle by which the axis must be at standstill.
    due: u64,
    /// The allowance has been extended for a stuck SYNC.
    sync_waited: bool,
}

/// Cycles a command may wait for its turn in the intake. A run has fewer senders (at most 4
/// clients, the driver, the fault injector, the quiet phase's client) than the intake serves
/// commands in a cycle (`COMMANDS_PER_CYCLE`, 8), so round robin serves each of them at
/// least once a cycle, and a command waits behind the ones its own sender sent before it.
/// Every sender sends at most one command a cycle but the fault injector, which sends at
/// most a start and an undo of each kind of fault at once. Two cycles more for the round
/// robin's cursor and for the cycle the command arrives in.
pub const QUEUE_CYCLES: u64 = 2 * Fault::ALL.len() as u64 + 2;

/// How long the controller waits at most for every drive to enable (`hold` out of OFF or
/// ERROR, `calibrate` out of OFF) before it gives up and answers: rt-core's
/// `ENABLE_TIMEOUT_NS` (2 s, private to `rt-core/src/controller/mod.rs`) or
/// `bus.boot_timeout_ms`, the longer.
fn enabling_wait_ns(cfg: &RobotConfig) -> u64 {
    2_000_000_000.max(u64::from(cfg.bus.boot_timeout_ms) * 1_000_000)
}

/// Cycles the planner may take to hand a line back: the request goes out at the end of the
/// cycle that asks for it, the plan comes in at the start of a later one (the simulation plans
/// inline: the next), and a request that finds the planner busy waits a cycle.
const LINE_PLANNING_CYCLES: u64 = 3;

/// How long a `move_linear` may wait for its answer [ns]: a line that comes during motion
/// first brings the running motion to rest, each axis within its acceleration and jerk limits
/// (rt-core's `Controller::stop_jerk_limited`), then is planned. From any velocity within the
/// axis's maximum and any acceleration within its limit, that stop lasts at most v/a + 2a/j
/// (a/j to bring the acceleration round, v/a to brake, a/j to end it); the longest axis's.
fn line_stop_ns(cfg: &RobotConfig) -> u64 {
    let longest = cfg
        .axes
        .iter()
        .map(|a| {
            let (v, acc) = (a.max_velocity_deg_s, a.max_acceleration_deg_s2);
            v / acc + a.max_jerk_deg_s3.map_or(0.0, |j| 2.0 * acc / j)
        })
        .fold(0.0, f64::max);
    (longest * 1e9).ceil() as u64
}

/// What a cycle's work cost: the allocations counted and the thread's CPU time.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Work {
    pub allocations: u64,
    pub cpu_ns: u64,
}

/// A broken invariant.
#[derive(Debug, Clone, PartialEq)]
pub struct Violation {
    pub cycle: u64,
    pub message: String,
    /// The quiet phase did not bring the arm back to a usable calibrated HOLD (rather than a
    /// per-cycle invariant broken).
    pub quiet_phase: bool,
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "cycle {}: {}", self.cycle, self.message)
    }
}

/// A command waiting for its answer.
#[derive(Debug, Clone, Copy)]
struct Asked {
    kind: u32,
    /// The axes a `calibrate` covers.
    which: Option<Which>,
    cycle: u64,
    /// The last cycle it may be answered in (a `calibrate` later while its calibration runs).
    due: u64,
}

impl Asked {
    /// A `calibrate`, answered when its calibration ends.
    fn waits_for_calibration(&self) -> bool {
        self.kind == CommandKind::Calibrate.to_wire()
    }
}

/// The checker of one run.
pub struct Checker {
    stops_deg: [(f64, f64); NUM_AXES],
    limits_deg: [(f64, f64); NUM_AXES],
    tolerance_deg: [f64; NUM_AXES],
    period_s: f64,
    /// Cycles the measured angle may lag the true one.
    lag_cycles: usize,
    /// The true speeds of the last `lag_cycles` plus [`DELAY_SYNCS`] cycles [deg/s], the
    /// newest last.
    recent_speeds: VecDeque<[f64; NUM_AXES]>,
    /// The true angles of the cycle before [deg].
    prev_true_deg: [f64; NUM_AXES],
    /// Per axis: the deceleration a stop brakes with at least (`braking_efficiency` times the
    /// maximum acceleration) [deg/s^2] and the braking check's latency [s].
    brake_decel_deg: [f64; NUM_AXES],
    braking_latency_s: [f64; NUM_AXES],
    /// The axes braking after a trip.
    stopping: [Option<Stopping>; NUM_AXES],
    /// Cycles the drives' enabling may take.
    enabling_cycles: u64,
    /// How long `identify_payload` may take to answer [cycles] (the clients' bound).
    identify_cycles: u64,
    /// How long `move_linear` may take to answer [cycles]: the stop before it and its planning.
    line_cycles: u64,
    /// The CPU time a cycle's work may take [ns].
    work_budget_ns: u64,
    /// The most CPU time a cycle's work took [ns].
    pub max_work_ns: u64,
    asked: HashMap<(u64, u64), Asked>,
    prev_mode: Mode,
    /// The previous cycle's `flags` and `axis_flags`: a refusal was decided on the state
    /// between the two published ones.
    prev_flags: u32,
    prev_axis_flags: [u32; NUM_AXES],
    left_off: bool,
    /// Per axis: the controller is not (yet again) responsible for its limits.
    excused: [bool; NUM_AXES],
    /// Per axis: its calibration in use was made while an obstacle or a push acted, which no
    /// stop-based calibration can tell from the stop (not judged against the truth until
    /// calibrated again: set when a `calibrate` covering it is answered OK); and the same of
    /// the calibration under way or last tried (a failed one gives the previous calibration
    /// back, which keeps its own).
    fooled: [bool; NUM_AXES],
    attempt_fooled: [bool; NUM_AXES],
    /// Each axis flagged calibrated in the last cycle.
    was_calibrated: [bool; NUM_AXES],
    /// An axis whose calibration an obstacle or a push fooled is measured off the truth by
    /// more than its tolerance in this cycle: the controller's picture of the arm is wrong
    /// (its gravity compensation of every axis too), so the stops it makes are not judged.
    fooled_off: bool,
    pub modes_reached: [u64; Mode::ALL.len()],
    pub answers: [u64; 3],
    /// The furthest the true angle went beyond a software limit while the controller was
    /// responsible for it [deg] (0: never beyond): how close the run came to breaking
    /// [`LIMIT_OVERRUN_DEG`].
    pub max_overrun_deg: f64,
    /// The kinematics the TCP's state is checked against.
    tcp: tcp::TcpCheck,
}

impl Checker {
    /// The checker of a run under `cfg`, of the simulated robot `sim` (its mechanical stops).
    pub fn new(cfg: &RobotConfig, sim: &SimBus) -> Checker {
        let safety = SafetyParams::from_config(cfg).with_jerk_limited_stop(cfg);
        let stops_deg = core::array::from_fn(|i| {
            let (lo, hi) = sim.arm().mechanical_stops(i);
            (lo.to_degrees(), hi.to_degrees())
        });
        Checker {
            stops_deg,
            limits_deg: core::array::from_fn(|i| (cfg.axes[i].min_deg, cfg.axes[i].max_deg)),
            tolerance_deg: core::array::from_fn(|i| cfg.axes[i].calibration.tolerance_deg),
            period_s: cfg.cycle_period_s(),
            // The position read in a cycle was sampled at the SYNC before and the truth is
            // the one after the cycle's physics (two cycles), and when TPDOs are lost the
            // master keeps the last one it got for up to `bus.max_missed_tpdos` cycles before
            // it declares the drive lost.
            lag_cycles: 2 + usize::from(cfg.bus.max_missed_tpdos),
            recent_speeds: VecDeque::new(),
            prev_true_deg: [0.0; NUM_AXES],
            brake_decel_deg: core::array::from_fn(|i| safety.brake_decel[i].to_degrees()),
            braking_latency_s: core::array::from_fn(|i| safety.braking_latency_s(i)),
            stopping: [None; NUM_AXES],
            enabling_cycles: enabling_wait_ns(cfg).div_ceil(cfg.cycle_period_ns()),
            identify_cycles: (core_reply_within(CommandKind::IdentifyPayload).as_nanos() as u64)
                .div_ceil(cfg.cycle_period_ns()),
            line_cycles: line_stop_ns(cfg).div_ceil(cfg.cycle_period_ns()) + LINE_PLANNING_CYCLES,
            work_budget_ns: cfg.work_budget_ns() * DEBUG_SLOWDOWN,
            max_work_ns: 0,
            asked: HashMap::new(),
            prev_mode: Mode::Off,
            prev_flags: 0,
            prev_axis_flags: [0; NUM_AXES],
            left_off: false,
            excused: [true; NUM_AXES],
            fooled: [false; NUM_AXES],
            attempt_fooled: [false; NUM_AXES],
            was_calibrated: [false; NUM_AXES],
            fooled_off: false,
            modes_reached: [0; Mode::ALL.len()],
            answers: [0; 3],
            max_overrun_deg: 0.0,
            tcp: tcp::TcpCheck::new(cfg),
        }
    }

    /// A command was sent at cycle `k`.
    pub fn asked(&mut self, c: &CommandSample, k: u64) {
        let which = match Request::decode(c) {
            Ok(Request::Calibrate(cal)) => Some(cal.which),
            _ => None,
        };
        let waits_for_enabling = matches!(
            CommandKind::try_from(c.kind),
            Ok(CommandKind::Hold | CommandKind::Calibrate)
        );
        let wait = if waits_for_enabling {
            QUEUE_CYCLES + self.enabling_cycles + 1
        } else if c.kind == CommandKind::IdentifyPayload.to_wire() {
            // Answered when its procedure ends, within the bound the clients wait.
            QUEUE_CYCLES + self.identify_cycles
        } else if c.kind == CommandKind::MoveLinear.to_wire() {
            // Answered once the motion under way has stopped and the line is planned.
            QUEUE_CYCLES + self.line_cycles
        } else {
            QUEUE_CYCLES
        };
        let a = Asked {
            kind: c.kind,
            which,
            cycle: k,
            due: k + wait,
        };
        self.asked.insert((c.client_id, c.request_id), a);
    }

    /// Commands not answered yet, the oldest first: (client, request, kind, cycle sent).
    pub fn unanswered(&self) -> Vec<(u64, u64, u32, u64)> {
        let mut v: Vec<_> = self
            .asked
            .iter()
            .map(|(&(c, r), a)| (c, r, a.kind, a.cycle))
            .collect();
        v.sort_by_key(|x| (x.3, x.0, x.1));
        v
    }

    /// Check cycle `k`: its published state, its replies, what it allocated, the faults under
    /// way.
    pub fn cycle(
        &mut self,
        k: u64,
        s: &StateSample,
        replies: &[Reply],
        served: &[CommandSample],
        work: Work,
        faults: &[Fault],
    ) -> Result<(), Violation> {
        let fail = |message: String| {
            let names: Vec<&str> = faults.iter().map(|f| f.name()).collect();
            Err(Violation {
                cycle: k,
                message: format!("{message}; faults under way: {names:?}"),
                quiet_phase: false,
            })
        };
        if work.allocations != 0 {
            return fail(format!(
                "the cycle's work allocated {} times",
                work.allocations
            ));
        }
        self.max_work_ns = self.max_work_ns.max(work.cpu_ns);
        if work.cpu_ns > self.work_budget_ns {
            return fail(format!(
                "the cycle's work took {} us of CPU time, more than its budget of {} us",
                work.cpu_ns / 1000,
                self.work_budget_ns / 1000
            ));
        }
        if let Some(what) = non_finite(s) {
            return fail(format!("a number of the state is not finite: {what}"));
        }
        let Ok(mode) = Mode::try_from(s.mode) else {
            return fail(format!("unknown mode {}", s.mode));
        };
        self.modes_reached[mode as usize] += 1;
        self.tcp.check(s).or_else(&fail)?;
        self.transition(mode, replies, served).or_else(&fail)?;
        self.positions(s, mode, faults).or_else(&fail)?;
        self.standstill(k, s, mode, faults).or_else(&fail)?;
        self.replies(s, mode, replies, served).or_else(&fail)?;
        if mode != Mode::Calibration {
            // The attempt ended: the end of its searches gave its axes its excuse; a failure
            // before it gave back the calibration before it, with that one's.
            self.attempt_fooled = [false; NUM_AXES];
        }
        self.overdue(k, mode).or_else(&fail)?;
        self.prev_mode = mode;
        self.prev_true_deg = s.sim_true_position;
        self.prev_flags = s.flags;
        self.prev_axis_flags = s.axis_flags;
        Ok(())
    }

    /// A command not answered by its due cycle (the oldest such), but a `calibrate` while a
    /// calibration runs.
    fn overdue(&self, k: u64, mode: Mode) -> Result<(), String> {
        let late = self
            .asked
            .iter()
            .filter(|(_, a)| k > a.due && !(a.waits_for_calibration() && mode == Mode::Calibration))
            .min_by_key(|(key, a)| (a.cycle, key.0, key.1));
        match late {
            Some((&(c, r), a)) => Err(format!(
                "client {c} request {r} (kind {}) sent in cycle {} not answered by cycle {} ({} cycles later), in {mode}",
                a.kind,
                a.cycle,
                a.due,
                a.due - a.cycle
            )),
            None => Ok(()),
        }
    }

    /// At the end of a run in cycle `k`, once the quiet phase brought the arm back to a usable
    /// HOLD with nothing waiting in the intake: no command may be left unanswered (its last
    /// `hold` ended every calibration and enabling under way).
    pub fn left_unanswered(&self, k: u64) -> Result<(), Violation> {
        let left = self.unanswered();
        if left.is_empty() {
            return Ok(());
        }
        Err(Violation {
            cycle: k,
            quiet_phase: false,
            message: format!(
                "{} commands left unanswered at the end of the run (client, request, kind, cycle sent; the oldest first): {:?}",
                left.len(),
                &left[..left.len().min(5)]
            ),
        })
    }

    /// The mode published after the cycle against the one before: a legal transition, or two
    /// through HOLD, a `hold` answered OK in the cycle and the command entering `mode` served
    /// after it (the mode in between is never published).
    fn transition(
        &mut self,
        mode: Mode,
        replies: &[Reply],
        served: &[CommandSample],
    ) -> Result<(), String> {
        let from = self.prev_mode;
        if mode == from {
            return Ok(());
        }
        let legal = match mode {
            Mode::Error | Mode::Hold => true,
            Mode::Off => !self.left_off,
            Mode::Calibration => matches!(from, Mode::Off | Mode::Hold),
            Mode::Release | Mode::TorqueControl | Mode::Pvt | Mode::VelocityControl => {
                from == Mode::Hold
            }
        } || entered_through_hold(mode, replies, served);
        if from == Mode::Off {
            self.left_off = true;
        }
        if legal {
            Ok(())
        } else {
            Err(format!("illegal mode transition {from} -> {mode}"))
        }
    }

    /// The fastest true speed of axis `i` over the newest `cycles` cycles [deg/s].
    fn fastest(&self, i: usize, cycles: usize) -> f64 {
        self.recent_speeds
            .iter()
            .rev()
            .take(cycles)
            .map(|v| v[i])
            .fold(0.0, f64::max)
    }

    fn positions(&mut self, s: &StateSample, mode: Mode, faults: &[Fault]) -> Result<(), String> {
        let outside_help = faults.iter().any(|f| f.moves_the_arm());
        let responsible = matches!(
            mode,
            Mode::Hold | Mode::Pvt | Mode::VelocityControl | Mode::TorqueControl | Mode::Error
        ) && !outside_help;
        if self.recent_speeds.len() == self.lag_cycles + DELAY_SYNCS {
            self.recent_speeds.pop_front();
        }
        self.recent_speeds
            .push_back(s.sim_true_velocity.map(f64::abs));
        let fooling = faults
            .iter()
            .any(|f| matches!(f, Fault::Obstacle | Fault::Push));
        let delayed = faults.contains(&Fault::BusDelay);
        self.fooled_off = false;
        if mode == Mode::Calibration {
            if self.prev_mode != Mode::Calibration {
                self.attempt_fooled = [false; NUM_AXES];
            }
            for f in &mut self.attempt_fooled {
                *f |= fooling;
            }
            // The searches ended: the offsets found are in force from now on, whatever the
            // `calibrate` is answered later (a trip during the move back fails it and keeps
            // them), and so is the attempt's excuse.
            for i in 0..NUM_AXES {
                if s.axis_flags[i] & AXIS_CALIBRATED != 0 && !self.was_calibrated[i] {
                    self.fooled[i] = self.attempt_fooled[i];
                }
            }
        }
        self.was_calibrated = s.axis_flags.map(|f| f & AXIS_CALIBRATED != 0);
        for i in 0..NUM_AXES {
            let q = s.sim_true_position[i];
            let (lo, hi) = self.stops_deg[i];
            if q < lo - STOP_PENETRATION_DEG || q > hi + STOP_PENETRATION_DEG {
                return Err(format!(
                    "axis {}: true angle {q:.3} deg beyond the mechanical stops [{lo:.3}, {hi:.3}] (+{STOP_PENETRATION_DEG} deg)",
                    i + 1
                ));
            }
            let calibrated = s.axis_flags[i] & AXIS_CALIBRATED != 0;
            let (lo, hi) = self.limits_deg[i];
            let inside = (lo..=hi).contains(&q);
            // A calibration an obstacle or a push fooled puts the axis where the controller
            // cannot know it is: its limits are not the controller's to keep (it measures the
            // axis as far from a limit as the calibration is off).
            let fooled = self.fooled[i] || self.attempt_fooled[i];
            let trusted = calibrated && !fooled;
            if !responsible || !trusted {
                self.excused[i] = true;
            }
            // The controller takes over an axis once it is inside and at rest: one that comes
            // in from a motion the controller was not responsible for (a calibration search
            // cut short at 30 deg/s next to a limit) is owed its stop first.
            // At rest over the cycles the measurement lags, not in one sample: the stop's first
            // set-point (the measured position, behind the true one) can halt an axis for an
            // instant before the stop's ramp takes it on.
            let at_rest = self.fastest(i, self.lag_cycles) < STANDSTILL_DEG_S;
            if inside && responsible && trusted && at_rest {
                self.excused[i] = false;
            }
            if !self.excused[i] {
                self.max_overrun_deg = self.max_overrun_deg.max(lo - q).max(q - hi);
            }
            if !self.excused[i] && (q < lo - LIMIT_OVERRUN_DEG || q > hi + LIMIT_OVERRUN_DEG) {
                return Err(format!(
                    "axis {}: true angle {q:.3} deg beyond the software limits [{lo}, {hi}] by more than {LIMIT_OVERRUN_DEG} deg in {mode} (velocity {:.3} deg/s)",
                    i + 1,
                    s.sim_true_velocity[i]
                ));
            }
            let err = (s.measured_position[i] - q).abs();
            let lag = self.lag_cycles + if delayed { DELAY_SYNCS } else { 0 };
            let speed = self.fastest(i, lag);
            let slack = self.tolerance_deg[i] + lag as f64 * speed * self.period_s;
            // A drive the master lost reports nothing: its axis's measured angle stands where
            // the last report left it, which says nothing about the calibration.
            let online = s.axis_flags[i] & AXIS_ONLINE != 0;
            if calibrated && fooled && err > slack {
                self.fooled_off = true;
            }
            if calibrated && online && !fooled && err > slack {
                return Err(format!(
                    "axis {}: flagged calibrated, but measured {:.4} deg vs true {q:.4} deg: off by {err:.4} deg, tolerance {slack:.4} deg",
                    i + 1,
                    s.measured_position[i]
                ));
            }
        }
        Ok(())
    }

    /// The braking after a trip: watched from the cycle ERROR is entered until standstill.
    /// Runs after [`Self::positions`], which has pushed this cycle's speeds.
    fn standstill(
        &mut self,
        k: u64,
        s: &StateSample,
        mode: Mode,
        faults: &[Fault],
    ) -> Result<(), String> {
        // A client's `hold` out of ERROR, and what follows it, commands the arm again.
        if mode != Mode::Error || faults.iter().any(|f| f.moves_the_arm()) || self.fooled_off {
            self.stopping = [None; NUM_AXES];
            return Ok(());
        }
        // ERROR just entered (the watches of an earlier ERROR ended when it was left).
        if !matches!(self.prev_mode, Mode::Error | Mode::Off) {
            for i in 0..NUM_AXES {
                let speed = self.fastest(i, self.lag_cycles);
                let v = s.sim_true_velocity[i];
                if speed < STANDSTILL_DEG_S {
                    continue;
                }
                let lag_s = self.lag_cycles as f64 * self.period_s;
                let latency_s = self.braking_latency_s[i] + lag_s;
                let a = self.brake_decel_deg[i];
                let direction = if v < 0.0 { -1.0 } else { 1.0 };
                // An axis a calibration search pressed into its mechanical stop springs back out
                // of it as its search ends: the controller's relax lets it, by up to its band.
                // In its stop in the cycle before the trip's, too: the trip's cycle restarts a
                // pressing axis's loop, and it may be out by the end of it.
                let q = s.sim_true_position[i];
                let (lo, hi) = self.stops_deg[i];
                let was = self.prev_true_deg[i];
                let springing_out =
                    (q.min(was) < lo && direction > 0.0) || (q.max(was) > hi && direction < 0.0);
                let relax_deg = if springing_out { SEARCH_RELAX_DEG } else { 0.0 };
                self.stopping[i] = Some(Stopping {
                    cycle: k,
                    from_deg: q,
                    direction,
                    speed,
                    allowed_deg: speed * latency_s
                        + speed * speed / (2.0 * a)
                        + STANDSTILL_SLACK_DEG
                        + relax_deg,
                    sync_waited: false,
                    travelled_deg: 0.0,
                    due: k
                        + ((latency_s + speed / a + STANDSTILL_SLACK_S) / self.period_s).ceil()
                            as u64,
                });
            }
        }
        let sync_stuck = faults.contains(&Fault::SyncStuck);
        for i in 0..NUM_AXES {
            let Some(st) = self.stopping[i].as_mut() else {
                continue;
            };
            // Without SYNC no drive applies a set-point, the controller's stop and power off
            // included: the drive's own SYNC watchdog stops the axis.
            if sync_stuck && !st.sync_waited {
                st.sync_waited = true;
                let watchdog_s = f64::from(SYNC_LOSS_PERIODS) * self.period_s;
                st.allowed_deg += s.sim_true_velocity[i].abs().max(st.speed) * watchdog_s;
                st.due += SYNC_LOSS_PERIODS as u64;
            }
            let travel = (s.sim_true_position[i] - st.from_deg) * st.direction;
            st.travelled_deg = st.travelled_deg.max(travel);
            if st.travelled_deg > st.allowed_deg {
                return Err(format!(
                    "axis {}: {:.3} deg travelled since the trip in cycle {} at {:.3} deg/s, more than its braking distance {:.3} deg (true angle {:.3} deg, velocity {:.3} deg/s, in {mode})",
                    i + 1,
                    st.travelled_deg,
                    st.cycle,
                    st.speed,
                    st.allowed_deg,
                    s.sim_true_position[i],
                    s.sim_true_velocity[i]
                ));
            }
            if s.sim_true_velocity[i].abs() < STANDSTILL_DEG_S {
                self.stopping[i] = None;
            } else if k > st.due {
                return Err(format!(
                    "axis {}: still at {:.3} deg/s in cycle {k}, {} cycles after the trip in cycle {} at {:.3} deg/s: its stop should have ended by cycle {} (in {mode})",
                    i + 1,
                    s.sim_true_velocity[i],
                    k - st.cycle,
                    st.cycle,
                    st.speed,
                    st.due
                ));
            }
        }
        Ok(())
    }

    fn replies(
        &mut self,
        s: &StateSample,
        mode: Mode,
        replies: &[Reply],
        served: &[CommandSample],
    ) -> Result<(), String> {
        for (n, r) in replies.iter().enumerate() {
            let Some(asked) = self.asked.remove(&(r.client_id, r.request_id)) else {
                return Err(format!(
                    "reply to client {} request {} (kind {}): never asked, or answered before",
                    r.client_id, r.request_id, r.kind
                ));
            };
            if asked.kind != r.kind && CommandKind::try_from(asked.kind).is_ok() {
                return Err(format!(
                    "client {} request {}: asked kind {}, answered as kind {}",
                    r.client_id, r.request_id, asked.kind, r.kind
                ));
            }
            if CommandKind::try_from(asked.kind).is_err() {
                // An unknown kind is refused, its number echoed (no `Response` can hold it).
                if r.status == 0 {
                    return Err(format!(
                        "client {} request {} of unknown kind {} answered OK",
                        r.client_id, r.request_id, asked.kind
                    ));
                }
                self.answers[1] += 1;
                continue;
            }
            let resp = Response::decode(r).map_err(|e| {
                format!(
                    "reply to client {} request {} does not decode: {e}",
                    r.client_id, r.request_id
                )
            })?;
            let slot = match resp.outcome {
                Outcome::Done(_) => 0,
                Outcome::Refused(_) => 1,
                Outcome::Failed(_) => 2,
            };
            self.answers[slot] += 1;
            if let Outcome::Refused(reason) = resp.outcome {
                self.refusal_true(s, mode, replies, n, resp.kind, reason)
                    .map_err(|e| format!("client {} request {}: {e}", r.client_id, r.request_id))?;
            }
            let Outcome::Done(done) = resp.outcome else {
                continue;
            };
            if resp.kind == CommandKind::Calibrate
                && let Some(which) = asked.which
            {
                // The axes it covered use the calibration just made from now on.
                for a in Axis::ALL.iter().filter(|a| which.contains(**a)) {
                    self.fooled[a.index()] = self.attempt_fooled[a.index()];
                }
            }
            // A later command of this cycle that may change the mode again: no conclusion.
            let later_change = replies[n + 1..].iter().any(|x| {
                x.status == 0
                    && CommandKind::try_from(x.kind).is_ok_and(|k| {
                        k.is_stop()
                            || k.needs_control()
                                && !matches!(
                                    k,
                                    CommandKind::SetTorques
                                        | CommandKind::SetVelocities
                                        | CommandKind::SetCartesianVelocity
                                        | CommandKind::PvtPoints
                                        | CommandKind::MoveAxis
                                        | CommandKind::MoveAll
                                )
                    })
            });
            if later_change {
                continue;
            }
            if resp.kind == CommandKind::Calibrate {
                // Answered OK only when the calibration ended with every axis it covered found.
                let Some(which) = asked.which else {
                    return Err(format!(
                        "calibrate of client {} request {} answered OK, but it did not decode as one",
                        r.client_id, r.request_id
                    ));
                };
                let missing = Axis::ALL.iter().find(|a| {
                    which.contains(**a) && s.axis_flags[a.index()] & AXIS_CALIBRATED == 0
                });
                if let Some(a) = missing {
                    return Err(format!(
                        "calibrate ({which:?}) of client {} request {} answered OK in {mode}, but axis {a} is not flagged calibrated (axis flags {:?})",
                        r.client_id, r.request_id, s.axis_flags
                    ));
                }
            }
            let entered = match resp.kind {
                // A `calibrate` served later in the cycle (answered when it ends) may have
                // started a calibration from that HOLD; one running before must have stopped.
                CommandKind::Hold
                    if mode == Mode::Calibration
                        && calibrate_served_after(served, r.client_id, r.request_id) =>
                {
                    None
                }
                CommandKind::Hold => Some(Mode::Hold),
                kind => mode_entered_by(kind),
            };
            if let Some(want) = entered
                && mode != want
                && mode != Mode::Error
            {
                return Err(format!(
                    "{} of client {} request {} answered OK ({done:?}) but the mode is {mode}, not {want}",
                    resp.kind, r.client_id, r.request_id
                ));
            }
        }
        Ok(())
    }
}

impl Checker {
    /// A refusal says what was so: the mode it names was the mode, the axis it names not
    /// calibrated, the emergency stop pressed (in the state published before the cycle or
    /// after it: the command was decided between the two), and a command refused did not
    /// enter its mode. Not judged where another command of the cycle changed the mode.
    fn refusal_true(
        &self,
        s: &StateSample,
        mode: Mode,
        replies: &[Reply],
        n: usize,
        kind: CommandKind,
        reason: Reason,
    ) -> Result<(), String> {
        let others_changed_mode = replies.iter().enumerate().any(|(m, x)| {
            m != n
                && x.status == 0
                && CommandKind::try_from(x.kind).is_ok_and(|k| {
                    // `release_control` by the owner brings what it drove to HOLD.
                    k.is_stop()
                        || k == CommandKind::Calibrate
                        || k == CommandKind::ReleaseControl
                        || mode_entered_by(k).is_some()
                })
        });
        let calibrated = |flags: &[u32; NUM_AXES], a: Axis| flags[a.index()] & AXIS_CALIBRATED != 0;
        match reason {
            Reason::WrongMode { mode: named }
                if !others_changed_mode && named != mode && named != self.prev_mode =>
            {
                return Err(format!(
                    "{kind} refused as not allowed in {named}, but the mode was {} before the cycle and {mode} after it",
                    self.prev_mode
                ));
            }
            Reason::NotCalibrated { axis }
                if calibrated(&self.prev_axis_flags, axis) && calibrated(&s.axis_flags, axis) =>
            {
                return Err(format!(
                    "{kind} refused as axis {axis} not calibrated, but it was flagged calibrated before the cycle and after it"
                ));
            }
            Reason::EmergencyStop if (self.prev_flags | s.flags) & STATE_ESTOP == 0 => {
                return Err(format!(
                    "{kind} refused for the emergency stop, but it was not pressed before the cycle nor after it"
                ));
            }
            _ => {}
        }
        if let Some(want) = mode_entered_by(kind)
            && mode == want
            && self.prev_mode != want
            && !others_changed_mode
        {
            return Err(format!(
                "{kind} refused ({reason}), but the mode went from {} to {want}",
                self.prev_mode
            ));
        }
        Ok(())
    }
}

/// Whether a `calibrate` was served after request `request_id` of client `client_id` in the
/// cycle that served `served`.
fn calibrate_served_after(served: &[CommandSample], client_id: u64, request_id: u64) -> bool {
    served
        .iter()
        .skip_while(|c| (c.client_id, c.request_id) != (client_id, request_id))
        .skip(1)
        .any(|c| c.kind == CommandKind::Calibrate.to_wire())
}

/// Whether a `hold` answered OK in this cycle was served before a command entering `mode`.
fn entered_through_hold(mode: Mode, replies: &[Reply], served: &[CommandSample]) -> bool {
    replies
        .iter()
        .filter(|r| r.status == 0 && r.kind == CommandKind::Hold.to_wire())
        .any(|hold| {
            served
                .iter()
                .skip_while(|c| (c.client_id, c.request_id) != (hold.client_id, hold.request_id))
                .skip(1)
                .filter_map(|c| CommandKind::try_from(c.kind).ok())
                .any(|k| {
                    mode_entered_by(k) == Some(mode)
                        || k == CommandKind::Calibrate && mode == Mode::Calibration
                })
        })
}

/// The mode a motion command enters when answered OK.
fn mode_entered_by(kind: CommandKind) -> Option<Mode> {
    match kind {
        CommandKind::Pvt => Some(Mode::Pvt),
        CommandKind::Release => Some(Mode::Release),
        CommandKind::TorqueControl => Some(Mode::TorqueControl),
        CommandKind::VelocityControl => Some(Mode::VelocityControl),
        _ => None,
    }
}

/// The first field of the state that is not finite, named with its value.
fn non_finite(s: &StateSample) -> Option<String> {
    let arrays: [(&str, &[f64; NUM_AXES]); 10] = [
        ("position", &s.position),
        ("velocity", &s.velocity),
        ("acceleration", &s.acceleration),
        ("current", &s.current),
        ("measured_position", &s.measured_position),
        ("commanded_position", &s.commanded_position),
        ("following_error", &s.following_error),
        ("i2t", &s.i2t),
        ("sim_true_position", &s.sim_true_position),
        ("sim_true_velocity", &s.sim_true_velocity),
    ];
    for (name, a) in arrays {
        if let Some(i) = a.iter().position(|x| !x.is_finite()) {
            return Some(format!("{name}[axis {}] = {}", i + 1, a[i]));
        }
    }
    let c = &s.cartesian;
    for (name, a) in [
        ("cartesian.position", &c.position[..]),
        ("cartesian.orientation", &c.orientation[..]),
        ("cartesian.linear_velocity", &c.linear_velocity[..]),
        ("cartesian.angular_velocity", &c.angular_velocity[..]),
    ] {
        if let Some(i) = a.iter().position(|x| !x.is_finite()) {
            return Some(format!("{name}[{i}] = {}", a[i]));
        }
    }
    let v = &s.last_error.values;
    v.iter()
        .position(|x| !x.is_finite())
        .map(|i| format!("last_error.values[{i}] = {}", v[i]))
}

#[cfg(test)]
mod tests;
