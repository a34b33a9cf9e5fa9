//! The controlled stop when `mcm-rt` is asked to stop (SIGTERM, SIGINT, its launcher dying).
//!
//! Runs inside the cycle: plain `Copy` data, no allocation. The runner asks once
//! ([`Controller::begin_shutdown`]); from the next step on the controller refuses every
//! command but `status` with [`Reason::ShuttingDown`], brings a moving arm to standstill with
//! the same controlled stop `hold` uses (each axis at its maximum deceleration), holds it for
//! [`SHUTDOWN_HOLD_NS`], then disables every drive (the `Disable` request: CiA 402 "disable
//! voltage" through the CANopen master) and reports [`ShutdownResult::Disabled`] once every
//! drive says so. When the bound passes first, it disables the drives at once and reports
//! [`ShutdownResult::TimedOut`]. The runner loops until [`Controller::shutdown_status`] says it
//! finished.

use super::Controller;
use super::exits::Exit;
use super::state::State;
use mcm_shared::NUM_AXES;
use mcm_shared::command::Request;
use mcm_shared::reply::Reason;

/// How long the arm is held at standstill before the drives are disabled (lets the arm settle
/// on the held position, as a brake would be engaged on an arm that has brakes).
pub const SHUTDOWN_HOLD_NS: u64 = 300_000_000;
/// The shortest bound of a shutdown (stop, hold, disable), whatever the axes' limits.
pub const SHUTDOWN_MIN_BOUND_NS: u64 = 2_000_000_000;
/// Time allowed for the drives to report disabled, on top of the stop and the hold.
const DISABLE_ALLOWANCE_NS: u64 = 500_000_000;

/// Where a shutdown is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShutdownPhase {
    /// Asked for; the next step starts it.
    Requested,
    /// The controlled stop runs.
    Stopping,
    /// At standstill, holding until this controller time.
    Holding { until_ns: u64 },
    /// The drives are asked to disable; waiting for them to say so.
    Disabling,
    /// Finished.
    Done(ShutdownResult),
}

/// How a shutdown ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShutdownResult {
    /// Standstill, held, every drive disabled, within the bound.
    Disabled,
    /// The bound passed in this phase; the drives were told to disable anyway.
    TimedOut { during: TimedOutPhase },
}

/// The phase a shutdown was in when its bound passed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimedOutPhase {
    Stopping,
    Holding,
    Disabling,
}

impl std::fmt::Display for ShutdownResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ShutdownResult::Disabled => write!(f, "arm at standstill, drives disabled"),
            ShutdownResult::TimedOut { during } => {
                let what = match during {
                    TimedOutPhase::Stopping => "while the arm was still stopping",
                    TimedOutPhase::Holding => "while holding at standstill",
                    TimedOutPhase::Disabling => "before every drive reported disabled",
                };
                write!(f, "bound reached {what}; drives told to disable anyway")
            }
        }
    }
}

/// A shutdown under way (controller time).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShutdownStatus {
    pub phase: ShutdownPhase,
    /// Controller time the shutdown started (its first step).
    pub started_ns: u64,
    /// Controller time by which it must be done.
    pub deadline_ns: u64,
    /// Controller time of the last step.
    pub now_ns: u64,
}

impl ShutdownStatus {
    /// The result, once finished.
    pub fn result(&self) -> Option<ShutdownResult> {
        match self.phase {
            ShutdownPhase::Done(r) => Some(r),
            _ => None,
        }
    }

    /// Controller time since the shutdown started [ns].
    pub fn elapsed_ns(&self) -> u64 {
        self.now_ns.saturating_sub(self.started_ns)
    }
}

impl Controller {
    /// Start the controlled stop and disable (idempotent); it runs from the next step on,
    /// bounded by [`Controller::shutdown_bound_ns`].
    pub fn begin_shutdown(&mut self) {
        if self.shutdown.is_none() {
            self.shutdown = Some(ShutdownStatus {
                phase: ShutdownPhase::Requested,
                started_ns: self.now_ns,
                deadline_ns: u64::MAX,
                now_ns: self.now_ns,
            });
        }
    }

    /// The shutdown, once asked for.
    pub fn shutdown_status(&self) -> Option<ShutdownStatus> {
        self.shutdown
    }

    /// How long a shutdown may take: the longest stop from each axis's maximum velocity at its
    /// maximum deceleration, the hold, and time for the drives to report disabled; at least
    /// [`SHUTDOWN_MIN_BOUND_NS`].
    pub fn shutdown_bound_ns(&self) -> u64 {
        let longest_stop_s = (0..NUM_AXES)
            .map(|i| self.p.limits[i].velocity / self.p.limits[i].acceleration)
            .fold(0.0, f64::max);
        let stop_ns = (longest_stop_s * 1e9) as u64;
        (stop_ns + SHUTDOWN_HOLD_NS + DISABLE_ALLOWANCE_NS).max(SHUTDOWN_MIN_BOUND_NS)
    }

    /// The bound passed on the wall clock (the controller's time lagged behind): disable the
    /// drives at the next step and report [`ShutdownResult::TimedOut`]. Does nothing unless a
    /// shutdown runs and has not finished.
    pub fn end_shutdown_now(&mut self) {
        let Some(mut s) = self.shutdown else {
            return;
        };
        let during = match s.phase {
            ShutdownPhase::Requested | ShutdownPhase::Stopping => TimedOutPhase::Stopping,
            ShutdownPhase::Holding { .. } => TimedOutPhase::Holding,
            ShutdownPhase::Disabling => TimedOutPhase::Disabling,
            ShutdownPhase::Done(_) => return,
        };
        // OFF: its motion step requests `Disable` of every drive.
        self.state = State::Off;
        s.phase = ShutdownPhase::Done(ShutdownResult::TimedOut { during });
        self.shutdown = Some(s);
    }

    /// While shutting down, refuse `req` (every request but `status`) with
    /// [`Reason::ShuttingDown`]; `true` when refused.
    pub(super) fn refused_for_shutdown(&mut self, c: super::state::Caller, req: &Request) -> bool {
        if self.shutdown.is_none() || matches!(req, Request::Status) {
            return false;
        }
        self.refuse(c, Reason::ShuttingDown);
        true
    }

    /// One step of the shutdown (after the commands, before the safety checks and the motion).
    pub(super) fn advance_shutdown(&mut self) {
        let Some(mut s) = self.shutdown else {
            return;
        };
        s.now_ns = self.now_ns;
        s.phase = match s.phase {
            ShutdownPhase::Requested => {
                s.started_ns = self.now_ns;
                s.deadline_ns = self.now_ns.saturating_add(self.shutdown_bound_ns());
                // What runs ends: the controlled stop `hold` uses, callers told why.
                self.leave(Exit::Shutdown);
                ShutdownPhase::Stopping
            }
            phase => phase,
        };
        s.phase = match s.phase {
            ShutdownPhase::Stopping if matches!(self.state, State::Off) => ShutdownPhase::Disabling,
            ShutdownPhase::Stopping if !self.state.planned_motion() => ShutdownPhase::Holding {
                until_ns: self.now_ns.saturating_add(SHUTDOWN_HOLD_NS),
            },
            ShutdownPhase::Holding { until_ns } if self.now_ns >= until_ns => {
                self.state = State::Off;
                ShutdownPhase::Disabling
            }
            ShutdownPhase::Disabling if self.master.feedback().iter().all(|f| !f.enabled) => {
                ShutdownPhase::Done(ShutdownResult::Disabled)
            }
            phase => phase,
        };
        let during = match s.phase {
            ShutdownPhase::Stopping => Some(TimedOutPhase::Stopping),
            ShutdownPhase::Holding { .. } => Some(TimedOutPhase::Holding),
            ShutdownPhase::Disabling => Some(TimedOutPhase::Disabling),
            ShutdownPhase::Requested | ShutdownPhase::Done(_) => None,
        };
        if let Some(during) = during
            && self.now_ns >= s.deadline_ns
        {
            self.state = State::Off;
            s.phase = ShutdownPhase::Done(ShutdownResult::TimedOut { during });
        }
        self.shutdown = Some(s);
        self.view.shutting_down = true;
    }
}

// Scenario tests on the whole simulated robot.
#[cfg(all(test, feature = "sim"))]
mod tests;
