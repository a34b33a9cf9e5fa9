//! `move_linear` (PVT mode): the TCP on a straight line, planned beside the cycle.
//!
//! Runs inside the cycle; the planning itself does not ([`crate::line_planner`]). The policy
//! (docs/protocol.md, "move_linear"; docs/cartesian.md, "During motion"):
//! - From rest the line is requested at once: the controller posts a [`LineRequest`] (the
//!   commanded position, the target), which [`crate::cycle::Cycle`] hands to the planner, and
//!   holds the arm where it is until the answer comes in a later cycle
//!   ([`Controller::line_planned`]). Then the line runs ([`LinePlan::sample`] gives each
//!   cycle's reference) and `move_linear` is answered with its duration and joint target, or
//!   refused with the planner's reason (`unreachable`, `out_of_range`, naming where on the
//!   path); a refused line moves nothing.
//! - During a move or a line, the planner plans from rest only: the running motion is first
//!   brought to rest from its present reference (each axis within its deceleration and jerk
//!   limits, the stop of `hold` with the jerk limits), then the line is requested from where
//!   it stopped. A `move_linear` while another waits supersedes it (the first is answered
//!   `aborted`).
//! - `move_axis`/`move_all` during a line re-plan from the line's present reference
//!   (`moves.rs`); `hold`, a gone owner, a trip stop it as they stop a move (and answer a
//!   waiting `move_linear` `aborted`, or with the trip's reason).
//! - During a PVT stream, or the stop after it ran dry: `busy`, as moves are.

use super::Controller;
use super::state::{Caller, LineRun, PendingLine, PvtMotion, State, Stopping};
use crate::line_planner::{LineRequest, Planned};
use crate::trajectory::{JointSample, StopPlan};
use mcm_kinematics::{LineError, LineTarget};
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Axis, MoveLinear};
use mcm_shared::reply::{Done, LineFault, MoveLinearPlan, Reason};
use mcm_shared::units::rad_to_deg6;
use nalgebra::Vector3;

impl Controller {
    /// `move_linear`: wait for the running motion to stop, then have the line planned.
    pub(super) fn on_move_linear(&mut self, c: Caller, m: MoveLinear) {
        let State::Pvt { motion, .. } = self.state else {
            return self.wrong_mode(c);
        };
        let stop = match motion {
            PvtMotion::Hold => None,
            PvtMotion::Move(_) | PvtMotion::Line(_) => self.stop_jerk_limited(),
            PvtMotion::LinePending(p) => {
                self.fail(p.caller, Reason::Aborted);
                p.stop
            }
            PvtMotion::Stop(_) | PvtMotion::Stream => return self.busy(c),
        };
        self.line_ids += 1;
        let target = LineTarget {
            position: Vector3::from(m.position),
            orientation: m.orientation.map(mcm_kinematics::rotation),
            velocity: m.velocity,
            acceleration: m.acceleration,
        };
        self.state = State::Pvt {
            motion: PvtMotion::LinePending(PendingLine {
                caller: c,
                request: LineRequest {
                    id: self.line_ids,
                    start: self.cmd.position,
                    target,
                },
                stop,
                posted: false,
            }),
            starved: false,
        };
    }

    /// The line requested and not yet handed to the planner (the cycle takes it after the
    /// step, [`crate::cycle::Cycle::step`]).
    pub fn take_line_request(&mut self) -> Option<LineRequest> {
        self.line_request.take()
    }

    /// The planner's answer (before the step of the cycle it arrives in): the line starts and
    /// `move_linear` is answered, or it is refused. An answer to a request that no longer
    /// waits (superseded, or the mode ended) is dropped.
    pub fn line_planned(&mut self, planned: &Planned) {
        let State::Pvt {
            motion: PvtMotion::LinePending(p),
            starved,
        } = self.state
        else {
            return;
        };
        if !p.posted || p.request.id != planned.id {
            return;
        }
        match &planned.result {
            Ok(plan) => {
                let duration = plan.duration();
                let joint_target_deg = rad_to_deg6(&plan.joint_target());
                self.line = Some(*plan);
                self.state = State::Pvt {
                    motion: PvtMotion::Line(LineRun { t: 0.0, duration }),
                    starved,
                };
                self.done(
                    p.caller,
                    Done::MoveLinear(MoveLinearPlan {
                        duration_s: duration,
                        joint_target_deg,
                    }),
                );
            }
            Err(e) => {
                self.state = State::Pvt {
                    motion: PvtMotion::Hold,
                    starved,
                };
                self.refuse(p.caller, line_refusal(e));
            }
        }
    }

    /// A waiting line by `dt`: its stop goes on; once at rest the request goes out (once).
    pub(super) fn advance_pending_line(&mut self, mut p: PendingLine, dt: f64) -> PvtMotion {
        p.stop = self.advance_stop(p.stop, dt);
        if p.stop.is_none() && !p.posted {
            p.request.start = self.cmd.position;
            p.posted = true;
            self.line_request = Some(p.request);
        }
        PvtMotion::LinePending(p)
    }

    /// A line by `dt`: the reference from its plan; HOLD's rest at its end.
    pub(super) fn advance_line(&mut self, run: LineRun, dt: f64) -> PvtMotion {
        let t = run.t + dt;
        let Some(s) = self.line.as_ref().map(|plan| plan.sample(t)) else {
            return PvtMotion::Hold;
        };
        let was = self.cmd.velocity;
        self.cmd = JointSample {
            position: s.q,
            velocity: s.qdot,
            acceleration: core::array::from_fn(|i| (s.qdot[i] - was[i]) / dt),
        };
        if t >= run.duration {
            self.cmd.velocity = [0.0; NUM_AXES];
            self.cmd.acceleration = [0.0; NUM_AXES];
            return PvtMotion::Hold;
        }
        PvtMotion::Line(LineRun { t, ..run })
    }

    /// The joint targets of the running line (`moves.rs` re-plans the axes a `move_axis`
    /// does not name to where the line was taking them).
    pub(super) fn line_joint_target(&self) -> Option<[f64; NUM_AXES]> {
        self.line.as_ref().map(|plan| plan.joint_target())
    }

    /// The running motion brought to rest from the commanded state, each axis within its
    /// deceleration and jerk limits; `None` when already at rest.
    fn stop_jerk_limited(&mut self) -> Option<Stopping> {
        let l = &self.p.limits;
        let plan = StopPlan::plan_from_state(
            self.cmd.position,
            self.cmd.velocity,
            self.cmd.acceleration,
            core::array::from_fn(|i| l[i].acceleration),
            core::array::from_fn(|i| l[i].jerk),
        );
        (plan.duration() > 0.0).then_some(Stopping { plan, t: 0.0 })
    }
}

/// The refusal of a line the planner would not plan: the fault and where on the path.
fn line_refusal(e: &LineError) -> Reason {
    let axis = |a: usize| Axis::ALL[a.clamp(1, NUM_AXES) - 1];
    match *e {
        LineError::NotFinite { value, .. } => Reason::OutOfRange {
            axis: None,
            value,
            min: f64::MIN,
            max: f64::MAX,
        },
        LineError::Argument { value, max, .. } => Reason::OutOfRange {
            axis: None,
            value,
            min: 0.0,
            max,
        },
        LineError::Limit { axis: a, value, .. } => Reason::OutOfRange {
            axis: Some(axis(a)),
            value,
            min: 0.0,
            max: f64::MAX,
        },
        LineError::Unreachable { at, .. } => Reason::LineUnreachable {
            axis: None,
            fault: LineFault::NoSolution {
                fraction: at.fraction,
            },
        },
        LineError::OutOfRange {
            at,
            axis: a,
            value_deg,
            min_deg,
            max_deg,
        } => Reason::LineOutOfRange {
            axis: axis(a),
            fault: LineFault::OutOfRange {
                fraction: at.fraction,
                value_deg,
                limit_deg: if value_deg > max_deg {
                    max_deg
                } else {
                    min_deg
                },
            },
        },
        LineError::Singular {
            at,
            singularity,
            value,
            margin,
        } => Reason::LineUnreachable {
            axis: None,
            fault: LineFault::Singular {
                fraction: at.fraction,
                singularity,
                value,
                margin,
            },
        },
        LineError::JointJump {
            at,
            axis: a,
            step_deg,
            allowed_deg,
            ..
        } => Reason::LineUnreachable {
            axis: Some(axis(a)),
            fault: LineFault::JointJump {
                fraction: at.fraction,
                step_deg,
                allowed_deg,
            },
        },
    }
}

// Scenario tests on the whole simulated robot.
#[cfg(all(test, feature = "sim"))]
mod tests;
