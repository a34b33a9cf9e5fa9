//! The controller's side of a calibration: starting the axes' searches, stepping them, putting
//! the offsets found in force once every selected axis found its own, the move back to zero,
//! and keeping the previous calibration when a calibration does not complete.
//!
//! Runs inside the cycle. While an axis searches it works in its raw (encoder) frame (its offset
//! is `None`); the offset it had is kept by its [`AxisCalibration`] and restored by
//! [`Controller::restore_previous_calibration`] when the calibration is aborted (`hold`, a mode
//! change by a lost owner, a shutdown, a safety trip) or fails; an axis that was searching its
//! mechanical stop then relaxes out of it (`calibrate_relax.rs`). Offsets found are written to
//! the drives (0x2100) only when they come into force.

use super::Controller;
use super::exits::Exit;
use super::state::{CalPhase, Caller, Moving, State};
use crate::calibration::{AxisCalibration, AxisInput, AxisSettings, Outcome};
use crate::canopen::AxisFeedback;
use crate::trajectory::{JointPlan, MovePlan};
use mcm_shared::NUM_AXES;
use mcm_shared::command::Axis;
use mcm_shared::reply::{CalibrationFailure, Reason};

/// Velocity factor of the move back to zero after calibration.
const RETURN_VELOCITY_FACTOR: f64 = 0.5;

impl Controller {
    /// Start the calibration searches of the axes that have settings.
    pub(super) fn start_calibration(
        &mut self,
        caller: Caller,
        settings: [Option<AxisSettings>; NUM_AXES],
    ) {
        let fb = *self.master.feedback();
        let mut axes = [None; NUM_AXES];
        for (i, s) in settings.iter().enumerate() {
            if let Some(s) = s {
                axes[i] = Some(AxisCalibration::start(
                    *s,
                    axis_input(&fb[i]),
                    self.offsets[i],
                ));
                self.offsets[i] = None;
            }
        }
        self.hold_here();
        self.state = State::Calibration {
            caller,
            phase: CalPhase::Search { axes },
        };
    }

    /// A calibration's searches end without completing: every axis of it gets back the offset
    /// it had (the commanded positions follow into the joint frame). Called before the state
    /// changes; nothing happens outside the searches.
    pub(super) fn restore_previous_calibration(&mut self) {
        let Some(axes) = self.searches() else {
            return;
        };
        for (i, cal) in axes.iter().enumerate() {
            let Some(cal) = cal else { continue };
            let now = self.offsets[i].unwrap_or(0.0);
            let prev = cal.previous();
            let shift = now - prev.unwrap_or(0.0);
            self.offsets[i] = prev;
            // The commanded positions (this cycle's and the two the following error is judged
            // against) move into the joint frame with the offset.
            self.cmd.position[i] += shift;
            for h in &mut self.cmd_hist {
                h[i] += shift;
            }
        }
    }

    /// The searches of the calibration under way; `None` outside them.
    pub(super) fn searches(&self) -> Option<[Option<AxisCalibration>; NUM_AXES]> {
        match self.state {
            State::Calibration {
                phase: CalPhase::Search { axes },
                ..
            } => Some(axes),
            _ => None,
        }
    }

    /// A drive rebooted (its encoder reference may be gone): the offset it had before the
    /// calibration is no longer kept.
    pub(super) fn forget_previous_calibration(&mut self, axis: usize) {
        if let State::Calibration {
            phase: CalPhase::Search { ref mut axes },
            ..
        } = self.state
            && let Some(Some(cal)) = axes.get_mut(axis)
        {
            cal.forget_previous();
        }
    }

    pub(super) fn advance_calibration(&mut self, caller: Caller, dt: f64) {
        let State::Calibration {
            phase: CalPhase::Search { mut axes },
            ..
        } = self.state
        else {
            return;
        };
        let fb = *self.master.feedback();
        let mut running = false;
        for (i, slot) in axes.iter_mut().enumerate() {
            // An axis that found its zero holds where it found it.
            let Some(cal) = slot.as_mut().filter(|c| c.outcome() == Outcome::Running) else {
                continue;
            };
            let out = cal.step(axis_input(&fb[i]), dt);
            // The raw target, in the joint frame of an uncalibrated axis (offset 0).
            self.cmd.position[i] = cal.target();
            self.current_limit[i] = cal.current_limit();
            match out {
                Outcome::Running => running = true,
                Outcome::Found { .. } => {}
                Outcome::Failed { cause } => {
                    let reason = Reason::CalibrationFailed {
                        axis: Axis::ALL[i],
                        cause,
                    };
                    // Found away from where the previous calibration puts it: one of the two
                    // is wrong, and the controller cannot tell which (an obstacle during
                    // either). The previous calibration is dropped, so that a later calibration
                    // can put it right (kept, it would refuse every new one for good).
                    if matches!(cause, CalibrationFailure::Implausible { .. }) {
                        cal.forget_previous();
                        self.master.forget_stored_calibration(i);
                        self.state = State::Calibration {
                            caller,
                            phase: CalPhase::Search { axes },
                        };
                    }
                    // ERROR with the controlled stop from the measured state
                    // (`Exit::SearchFailed`): the caller hears of the failure, and the incident
                    // is recorded; every axis keeps its previous calibration.
                    self.leave(Exit::SearchFailed(reason));
                    self.report_incident(reason);
                    return;
                }
            }
        }
        if running {
            self.state = State::Calibration {
                caller,
                phase: CalPhase::Search { axes },
            };
            return;
        }
        // Every axis found its zero: the offsets come into force (and into the drives, which
        // keep them until they lose power), then the axes of this calibration move back to
        // zero (the others stay where they are).
        for (i, cal) in axes.iter().enumerate() {
            if let Some(Outcome::Found { offset }) = cal.map(|c| c.outcome()) {
                self.offsets[i] = Some(offset);
                let counts = (offset * self.p.counts_per_rad[i])
                    .round()
                    .clamp(f64::from(i32::MIN), f64::from(i32::MAX));
                self.master.store_calibration(i, counts as i32);
                // The commanded positions (this cycle's and the two the following error is
                // judged against) move into the joint frame with the offset.
                self.cmd.position[i] -= offset;
                for h in &mut self.cmd_hist {
                    h[i] -= offset;
                }
            }
        }
        let start = self.cmd.position;
        let target: [f64; NUM_AXES] =
            core::array::from_fn(|i| if axes[i].is_some() { 0.0 } else { start[i] });
        let plan = MovePlan::plan(start, target, &self.p.limits, RETURN_VELOCITY_FACTOR)
            .and_then(|plan| JointPlan::from_move(&plan));
        match plan {
            Ok(plan) => {
                self.state = State::Calibration {
                    caller,
                    phase: CalPhase::Return(Moving { plan }),
                }
            }
            // Calibration done.
            Err(_) => self.arrive_in_hold(caller),
        }
    }
}

/// An axis's feedback as its calibration needs it.
fn axis_input(fb: &AxisFeedback) -> AxisInput {
    AxisInput {
        position: fb.position_rad,
        current: fb.current_a,
        light_barrier: fb.light_barrier,
    }
}

// Scenario tests on the whole simulated robot.
#[cfg(all(test, feature = "sim"))]
mod tests;
