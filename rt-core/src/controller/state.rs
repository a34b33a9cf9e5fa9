//! The controller's operating state: one enum whose variants carry the data of their mode, so
//! that a combination the modes forbid (a calibration reply waiting in PVT, a stream starving
//! in HOLD, a torque deadline in RELEASE) cannot be represented. The wire mode
//! ([`mcm_shared::mode::Mode`]) is derived from it.
//!
//! Runs inside the cycle: plain `Copy` data, no allocation.

use super::identify_payload::Identification;
use super::velocity::VelocityTarget;
use crate::calibration::{AxisCalibration, AxisSettings};
use crate::line_planner::LineRequest;
use crate::trajectory::{JointPlan, StopPlan};
use mcm_shared::NUM_AXES;
use mcm_shared::mode::{CommandKind, Mode};

/// The timeout of TORQUE_CONTROL and VELOCITY_CONTROL: the mode ends (the controlled stop to
/// HOLD) when its set command does not come within `timeout_ns` of the last one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Watchdog {
    timeout_ns: u64,
    /// Controller time by which the next set command must arrive.
    deadline_ns: u64,
}

impl Watchdog {
    /// The mode's `timeout_s` (`None`: no timeout), running from `now_ns`.
    pub fn start(timeout_s: Option<f64>, now_ns: u64) -> Option<Watchdog> {
        timeout_s.map(|t| {
            let timeout_ns = (t * 1e9) as u64;
            Watchdog {
                timeout_ns,
                deadline_ns: now_ns.saturating_add(timeout_ns),
            }
        })
    }

    /// A set command arrived at `now_ns`.
    pub fn fed(self, now_ns: u64) -> Watchdog {
        Watchdog {
            deadline_ns: now_ns.saturating_add(self.timeout_ns),
            ..self
        }
    }

    /// The deadline passed.
    pub fn expired(&self, now_ns: u64) -> bool {
        now_ns > self.deadline_ns
    }
}

/// Who asked: the ids and kind a reply (now or later) is addressed with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Caller {
    pub client_id: u64,
    pub request_id: u64,
    pub kind: CommandKind,
}

/// A planned move in progress (`move_axis`, `move_all`, the return after calibration): one
/// plan per axis, each with its own clock (an axis not moving holds its position).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Moving {
    pub plan: JointPlan,
}

/// A controlled stop in progress; the axes hold where it ends.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stopping {
    pub plan: StopPlan,
    /// Time since start [s].
    pub t: f64,
}

/// What the axes do in PVT mode.
// A stop plan is large; boxing it would allocate inside the cycle.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy)]
pub(crate) enum PvtMotion {
    /// Keep the commanded position.
    Hold,
    Move(Moving),
    Stop(Stopping),
    /// Follow the PVT stream.
    Stream,
    /// A `move_linear` waits: the running motion comes to rest, then its line is planned
    /// beside the cycle (`linear.rs`); the arm holds meanwhile.
    LinePending(PendingLine),
    /// A `move_linear` line under way (its plan is the controller's `line`).
    Line(LineRun),
}

/// A `move_linear` until its line runs.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PendingLine {
    pub caller: Caller,
    /// The request, its `start` set when it is posted.
    pub request: LineRequest,
    /// The motion that ran coming to rest first (`None`: at rest).
    pub stop: Option<Stopping>,
    /// The request went out to the planner.
    pub posted: bool,
}

/// A line under way: `t` seconds since it started, of `duration`. The plan itself (13 kB) is
/// the controller's `line`; its duration is kept here too so that the state alone says how
/// long its motion has left ([`State::remaining`]), as it does for every other motion.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LineRun {
    pub t: f64,
    pub duration: f64,
}

/// What a calibration is doing.
// The searches are large; boxing them would allocate inside the cycle.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy)]
pub(crate) enum CalPhase {
    /// Searches in the raw frame: `Some` for every axis this calibration covers, from its
    /// start to its end. Each keeps the offset its axis had (restored if the calibration does
    /// not complete) and, once found, the new one (in force only once every covered axis
    /// found its own).
    Search {
        axes: [Option<AxisCalibration>; NUM_AXES],
    },
    /// Every axis found its zero: the move of the selected axes back to zero.
    Return(Moving),
}

/// The mode an enabling that fails falls back to (the wire mode while enabling).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Before {
    Off,
    Error,
}

/// What follows once every drive is enabled.
// The calibration settings are large; boxing them would allocate inside the cycle.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy)]
pub(crate) enum After {
    /// `hold`: HOLD, and its reply.
    Hold,
    /// `calibrate` from OFF: the calibration with these per-axis settings.
    Calibrate([Option<AxisSettings>; NUM_AXES]),
    /// A `calibrate` whose owner went away while the drives were being enabled for it: HOLD
    /// without calibrating, and the `calibrate` answered `aborted` (an OK would tell its
    /// caller the axes were calibrated).
    HoldAborted,
}

/// The controller's mode and the data only that mode has.
// The calibration variant is large; boxing it would allocate inside the cycle.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy)]
pub(crate) enum State {
    /// Drives disabled; the commanded position follows the measured one.
    Off,
    /// Enabling every drive (holding where it is) before HOLD or a calibration.
    Enabling {
        caller: Caller,
        /// Controller time by which every drive must be enabled.
        deadline_ns: u64,
        from: Before,
        then: After,
    },
    Hold {
        stop: Option<Stopping>,
    },
    Calibration {
        caller: Caller,
        phase: CalPhase,
    },
    /// `identify_payload`: a procedure of HOLD (the wire mode stays HOLD) that moves the wrist
    /// through poses and measures what the drives hold there (`identify_payload.rs`).
    Identify {
        caller: Caller,
        run: Identification,
    },
    Pvt {
        motion: PvtMotion,
        /// The stream ran dry while moving (cleared by the next move, batch or PVT entry).
        starved: bool,
    },
    /// Gravity and friction compensation.
    Release,
    /// External torques.
    Torque {
        torques: [f64; NUM_AXES],
        gravity: bool,
        /// Fed by `set_torques` (`None`: no timeout).
        watchdog: Option<Watchdog>,
    },
    /// Joint velocities from `set_velocities`, or from the TCP's velocity of
    /// `set_cartesian_velocity`, ramped (`velocity.rs`).
    Velocity {
        target: VelocityTarget,
        /// Fed by `set_velocities` and `set_cartesian_velocity` (`None`: no timeout).
        watchdog: Option<Watchdog>,
    },
    /// After a safety trip: the quick stop, then holding (drives that dropped out stay off).
    Error {
        stop: Option<Stopping>,
        /// Cycles left in which an axis that tripped its following error follows its measured
        /// position, its drive's loop restarted at the start (`trips.rs`), so
        /// that it does not press into what held it. They end with the mode.
        relax: [u8; NUM_AXES],
    },
}

impl State {
    /// ERROR with the stop `stop` and no axis relaxing.
    pub fn error(stop: Option<Stopping>) -> State {
        State::Error {
            stop,
            relax: [0; NUM_AXES],
        }
    }

    /// The wire mode: an enabling reports the mode it started from.
    pub fn mode(&self) -> Mode {
        match self {
            State::Off
            | State::Enabling {
                from: Before::Off, ..
            } => Mode::Off,
            State::Enabling {
                from: Before::Error,
                ..
            }
            | State::Error { .. } => Mode::Error,
            State::Hold { .. } | State::Identify { .. } => Mode::Hold,
            State::Calibration { .. } => Mode::Calibration,
            State::Pvt { .. } => Mode::Pvt,
            State::Release => Mode::Release,
            State::Torque { .. } => Mode::TorqueControl,
            State::Velocity { .. } => Mode::VelocityControl,
        }
    }

    /// A planned move or controlled stop runs (validated when planned: its whole path lies in
    /// the reachable range).
    pub fn planned_motion(&self) -> bool {
        self.remaining().is_some()
    }

    /// Seconds until the planned move or stop ends; `None` when none runs.
    pub fn remaining(&self) -> Option<f64> {
        let stop = |s: &Stopping| (s.plan.duration() - s.t).max(0.0);
        let mv = |m: &Moving| m.plan.remaining();
        match self {
            State::Hold { stop: Some(s) }
            | State::Error { stop: Some(s), .. }
            | State::Pvt {
                motion: PvtMotion::Stop(s),
                ..
            } => Some(stop(s)),
            State::Pvt {
                motion: PvtMotion::Move(m),
                ..
            }
            | State::Calibration {
                phase: CalPhase::Return(m),
                ..
            } => Some(mv(m)),
            State::Identify { run, .. } => run.moving().map(mv),
            State::Pvt {
                motion: PvtMotion::LinePending(p),
                ..
            } => Some(p.stop.as_ref().map_or(0.0, stop)),
            State::Pvt {
                motion: PvtMotion::Line(l),
                ..
            } => Some((l.duration - l.t).max(0.0)),
            _ => None,
        }
    }
}

impl Before {
    /// The state an enabling that failed returns to.
    pub fn state(self) -> State {
        match self {
            Before::Off => State::Off,
            Before::Error => State::error(None),
        }
    }
}
