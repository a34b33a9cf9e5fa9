//! `move_axis` and `move_all` (PVT mode): planned from the commanded state, also while axes
//! move.
//!
//! Runs inside the cycle. The policy (docs/protocol.md, "move_axis, move_all"):
//! - A move received while a move runs re-plans from the current commanded position, velocity
//!   and acceleration of each axis it covers ([`crate::trajectory::online`]): no step in
//!   velocity, none in acceleration beyond the jerk limit.
//! - Each axis has its own plan: `move_axis` replaces the plan of its axis only; the others
//!   carry on. `move_all` replaces all six: from rest (no plan running) the phase-synchronised
//!   straight line ([`MovePlan`]), during motion each axis re-planned from its own state.
//! - The `move_all` result describes the new plan.
//! - A move during a PVT stream, or during the stop after a stream ran dry, is refused `busy`
//!   (as `pvt_points` during a move is).
//! - Every new plan stays within the reachable range (the limits less the safety margin),
//!   including where a re-planned axis overshoots before turning back; otherwise the move is
//!   refused `unreachable` and the running plans carry on.

use super::Controller;
use super::state::{Caller, Moving, PvtMotion, State};
use crate::trajectory::{AxisPlan, JointPlan, MovePlan, plan_from_state};
use mcm_shared::NUM_AXES;
use mcm_shared::command::Axis;
use mcm_shared::ranges::{Arg, ArgRefusal};
use mcm_shared::reply::{Done, MoveAllPlan, Reason};
use mcm_shared::units::{rad_to_deg, rad_to_deg6};

/// Positions closer than this are the same position [rad] (a nanoradian: far below one
/// encoder count, above the planners' rounding): a target this close to the commanded
/// position is that position, and a plan may pass the reachable range by this much.
const POSITION_RESOLUTION_RAD: f64 = 1e-9;

/// The refusal of a velocity factor the planner cannot use (decoding checked its range; a plan
/// that still fails names it).
fn factor_refused(factor: f64) -> Reason {
    let (min, max) = Arg::VelocityFactor.fixed_bounds();
    Reason::InvalidArgument {
        refusal: ArgRefusal {
            arg: Arg::VelocityFactor,
            axis: None,
            value: factor,
            min,
            max,
        },
    }
}

impl Controller {
    /// A move to `target` [rad] (of axis `only`, or of all axes). `move_all` answers with the
    /// plan; `move_axis` with a plain acknowledgement.
    pub(super) fn on_move(
        &mut self,
        c: Caller,
        mut target: [f64; NUM_AXES],
        factor: f64,
        only: Option<Axis>,
    ) {
        let State::Pvt { motion, .. } = self.state else {
            return self.wrong_mode(c);
        };
        let running = match motion {
            PvtMotion::Hold => None,
            PvtMotion::Move(m) => Some(m.plan),
            // The axes a `move_axis` does not name go on to where the line was taking them,
            // each re-planned from its present reference.
            PvtMotion::Line(_) => {
                let to = self.line_joint_target().unwrap_or(self.cmd.position);
                let mut axes = [AxisPlan::hold(0.0); NUM_AXES];
                for (i, axis) in axes.iter_mut().enumerate() {
                    *axis = match self.plan_axis(i, to[i], factor) {
                        Ok(plan) => plan,
                        Err(reason) => return self.refuse(c, reason),
                    };
                }
                Some(JointPlan::new(axes))
            }
            // A line still being planned, the arm at rest: superseded (`start_moving`).
            PvtMotion::LinePending(p) if p.stop.is_none() => None,
            PvtMotion::Stop(_) | PvtMotion::Stream | PvtMotion::LinePending(_) => {
                return self.busy(c);
            }
        };
        for (i, q) in target.iter().copied().enumerate() {
            if only.is_some_and(|a| a.index() != i) {
                continue;
            }
            if !self.p.reachable(i, q) {
                return self.refuse(c, self.unreachable(i, q));
            }
        }
        // A target within [`POSITION_RESOLUTION_RAD`] of the commanded position is that position:
        // a move of a tiny (even subnormal) distance is no move, not an unplannable one.
        for (q, at) in target.iter_mut().zip(self.cmd.position) {
            if (*q - at).abs() < POSITION_RESOLUTION_RAD {
                *q = at;
            }
        }
        if let Some(axis) = only {
            let i = axis.index();
            let plan = match self.plan_axis(i, target[i], factor) {
                Ok(plan) => plan,
                Err(reason) => return self.refuse(c, reason),
            };
            let mut joint = running.unwrap_or_else(|| JointPlan::hold(self.cmd.position));
            joint.set_axis(i, plan);
            self.start_moving(joint);
            return self.done(c, Done::Ack);
        }
        let (joint, result) = if running.is_none() {
            // From rest: the straight line in joint space.
            let planned = MovePlan::plan(self.cmd.position, target, &self.p.limits, factor)
                .and_then(|plan| JointPlan::from_move(&plan).map(|joint| (plan, joint)));
            let Ok((plan, joint)) = planned else {
                return self.refuse(c, factor_refused(factor));
            };
            let result = MoveAllPlan {
                velocities_deg_s: rad_to_deg6(&plan.velocities()),
                longest: Axis::ALL[plan.longest_axis().min(NUM_AXES - 1)],
                duration_s: plan.duration(),
            };
            (joint, result)
        } else {
            // During motion: each axis from its own commanded state.
            let mut axes = [AxisPlan::hold(0.0); NUM_AXES];
            for (i, axis) in axes.iter_mut().enumerate() {
                *axis = match self.plan_axis(i, target[i], factor) {
                    Ok(plan) => plan,
                    Err(reason) => return self.refuse(c, reason),
                };
            }
            let mut longest = 0;
            for i in 1..NUM_AXES {
                if axes[i].duration() > axes[longest].duration() {
                    longest = i;
                }
            }
            let result = MoveAllPlan {
                velocities_deg_s: rad_to_deg6(&axes.map(|a| a.peak_velocity())),
                longest: Axis::ALL[longest],
                duration_s: axes[longest].duration(),
            };
            (JointPlan::new(axes), result)
        };
        self.start_moving(joint);
        self.done(c, Done::MoveAll(result));
    }

    fn start_moving(&mut self, plan: JointPlan) {
        if let State::Pvt {
            motion: PvtMotion::LinePending(p),
            ..
        } = self.state
        {
            self.fail(p.caller, Reason::Aborted);
        }
        self.state = State::Pvt {
            motion: PvtMotion::Move(Moving { plan }),
            starved: false,
        };
    }

    /// Axis `i` from its commanded state to `target` [rad]; refused when the factor is not
    /// allowed or the plan would leave the reachable range (beyond where the axis is now).
    fn plan_axis(&self, i: usize, target: f64, factor: f64) -> Result<AxisPlan, Reason> {
        let (p, v, a) = (
            self.cmd.position[i],
            self.cmd.velocity[i],
            self.cmd.acceleration[i],
        );
        let plan = plan_from_state(i, p, v, a, target, self.p.limits[i], factor)
            .map_err(|_| factor_refused(factor))?;
        let (lo, hi) = plan.position_range();
        let max = self.p.reach_max[i].max(p) + POSITION_RESOLUTION_RAD;
        let min = self.p.reach_min[i].min(p) - POSITION_RESOLUTION_RAD;
        if hi > max {
            return Err(self.unreachable(i, hi));
        }
        if lo < min {
            return Err(self.unreachable(i, lo));
        }
        Ok(plan)
    }

    pub(super) fn unreachable(&self, i: usize, q: f64) -> Reason {
        Reason::Unreachable {
            axis: Axis::ALL[i],
            target_deg: rad_to_deg(q),
            min_deg: rad_to_deg(self.p.reach_min[i]),
            max_deg: rad_to_deg(self.p.reach_max[i]),
        }
    }
}

// Scenario tests on the whole simulated robot.
#[cfg(all(test, feature = "sim"))]
mod tests;
