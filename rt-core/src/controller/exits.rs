//! Leaving a mode: the one path by which whatever runs ends before its time, and what leaving
//! each mode needs.
//!
//! Runs inside the cycle: plain `Copy` data, no allocation.
//!
//! A mode ends early for one of the reasons of [`Exit`]: a `hold`, the owner releasing control
//! or going away (`ownership.rs`), `mcm-rt` shutting down (`shutdown_sequence.rs`), the timeout
//! of TORQUE_CONTROL or VELOCITY_CONTROL (`motion.rs`, `velocity.rs`), a safety trip
//! (`trips.rs`) or a failed calibration search (`calibrate.rs`). [`Controller::leave`] runs the
//! exit hook of the mode that ends, then starts the mode the exit leads to:
//! - OFF and ERROR stay as they are (a trip in OFF is only reported; ERROR keeps its stop).
//! - HOLD stays (a stop under way goes on), except after a trip: ERROR.
//! - An enabling goes on after a timeout (a `hold` starts it anew: `begin_enabling`); when its
//!   owner is gone it ends in HOLD instead of starting a calibration, and a `calibrate` that
//!   started it is then answered `aborted` (never OK: nothing was calibrated). A shutdown or a trip
//!   fails its caller (`shutting_down`, or the trip's reason) and it falls back to the mode it
//!   started from (OFF or ERROR).
//! - CALIBRATION: every axis it was searching gets the calibration it had back
//!   ([`Controller::restore_previous_calibration`]) and its caller is failed (`aborted` after a
//!   `hold`, a gone owner or a timeout, `shutting_down`, or the reason of the trip or of the
//!   failed search). Each axis that was searching its mechanical stop relaxes out of the
//!   stop's spring once every stop has ended ([`Controller::relax_searched_axes`]): held at
//!   its measured position there, its drive would press with the full current for good; then
//!   as below.
//! - `identify_payload` (a procedure of HOLD): its caller is failed as a calibration's is, then
//!   as below.
//! - PVT (a move, a stop or a stream), RELEASE, TORQUE_CONTROL, VELOCITY_CONTROL, CALIBRATION:
//!   HOLD with the controlled stop `hold` uses ([`Controller::stop_motion`]: from the commanded
//!   state in the position modes, from the measured state in the torque modes and the
//!   calibration searches); after a trip ERROR with the quick stop; after a failed calibration
//!   search ERROR with that controlled stop from the measured state: the axis that failed
//!   stands (it was blocked, or its search ended), but the others may still search at full
//!   speed, and a reference commanded at the measured position with no stop would leave each
//!   drive's position loop to brake it as hard and as far as it happens to, not within the
//!   braking distance the safety checks count on. Only a calibration search fails so: a
//!   failed search anywhere else is taken as a trip (and is a bug, which a debug build
//!   asserts).
//!
//! The PVT queue is left as it is: entering PVT again empties it.

use super::Controller;
use super::state::{After, Before, CalPhase, Caller, PvtMotion, State};
use mcm_shared::reply::Reason;

/// Why the mode that runs ends before its time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Exit {
    /// A `hold` command.
    Hold,
    /// The owner released control or is gone: what it drove comes to HOLD.
    OwnerGone,
    /// `mcm-rt` is shutting down.
    Shutdown,
    /// The set command of TORQUE_CONTROL or VELOCITY_CONTROL did not come within its timeout.
    Timeout,
    /// A safety check or drive error.
    Trip(Reason),
    /// A calibration search failed: ERROR with the controlled stop of `hold` from the measured
    /// state (the other axes may still search at speed). Taken only by a calibration search.
    SearchFailed(Reason),
}

impl Exit {
    /// What a command waiting for the mode's end (a calibration, an enabling) is answered.
    pub fn reason(self) -> Reason {
        match self {
            Exit::Hold | Exit::OwnerGone | Exit::Timeout => Reason::Aborted,
            Exit::Shutdown => Reason::ShuttingDown,
            Exit::Trip(reason) | Exit::SearchFailed(reason) => reason,
        }
    }

    /// The exit leads to ERROR.
    fn trips(self) -> bool {
        matches!(self, Exit::Trip(_) | Exit::SearchFailed(_))
    }

    /// The exit as a mode other than a calibration search takes it: a failed search is a trip.
    fn outside_a_search(self) -> Exit {
        match self {
            Exit::SearchFailed(reason) => Exit::Trip(reason),
            why => why,
        }
    }
}

impl Controller {
    /// End the mode that runs for `why` (see the module doc): the mode's exit hook, then the
    /// mode the exit leads to. An exit that does not end the mode changes nothing.
    pub(super) fn leave(&mut self, why: Exit) {
        let searching = matches!(
            self.state,
            State::Calibration {
                phase: CalPhase::Search { .. },
                ..
            }
        );
        debug_assert!(
            searching || !matches!(why, Exit::SearchFailed(_)),
            "{why:?} outside a calibration search"
        );
        let why = if searching {
            why
        } else {
            why.outside_a_search()
        };
        self.state = match self.state {
            s @ (State::Off | State::Error { .. }) => s,
            s @ State::Hold { .. } if !why.trips() => s,
            State::Enabling {
                caller,
                deadline_ns,
                from,
                then,
            } => match why {
                Exit::Hold | Exit::Timeout => return,
                // A `hold` is still done when the drives are enabled; a `calibrate` is not.
                Exit::OwnerGone => State::Enabling {
                    caller,
                    deadline_ns,
                    from,
                    then: match then {
                        After::Hold => After::Hold,
                        After::Calibrate(_) | After::HoldAborted => After::HoldAborted,
                    },
                },
                Exit::Shutdown | Exit::Trip(_) | Exit::SearchFailed(_) => {
                    self.enabling_failed(caller, from, why.reason())
                }
            },
            State::Calibration { caller, .. } => {
                self.relax_searched_axes();
                self.restore_previous_calibration();
                self.fail(caller, why.reason());
                self.stop_for(why)
            }
            State::Identify { caller, .. } => {
                self.fail(caller, why.reason());
                self.stop_for(why)
            }
            State::Pvt {
                motion: PvtMotion::LinePending(p),
                ..
            } => {
                self.fail(p.caller, why.reason());
                self.stop_for(why)
            }
            State::Hold { .. }
            | State::Pvt { .. }
            | State::Release
            | State::Torque { .. }
            | State::Velocity { .. } => self.stop_for(why),
        };
    }

    /// An enabling ends without every drive enabled: its caller is told `reason`; the state it
    /// falls back to.
    pub(super) fn enabling_failed(
        &mut self,
        caller: Caller,
        from: Before,
        reason: Reason,
    ) -> State {
        self.fail(caller, reason);
        from.state()
    }

    /// The mode `why` leads to, with its stop planned from the mode that ends (the caller sets
    /// the state).
    fn stop_for(&mut self, why: Exit) -> State {
        match why {
            Exit::Trip(reason) => State::Error {
                stop: self.quick_stop(),
                relax: super::trips::relax_after(reason, &self.i2t.derated()),
            },
            Exit::SearchFailed(_) => State::error(self.stop_motion()),
            Exit::Hold | Exit::OwnerGone | Exit::Shutdown | Exit::Timeout => State::Hold {
                stop: self.stop_motion(),
            },
        }
    }
}

// Scenario tests on the whole simulated robot.
#[cfg(all(test, feature = "sim"))]
mod tests;
