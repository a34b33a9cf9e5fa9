//! The plan against the axis limits, sampled: every knot (the end of the segment before it and
//! the start of the one after it, where the acceleration may step) and every multiple of `dt`
//! in between. Positions must lie in the reachable range, speeds and accelerations within the
//! axis limits, up to round-off ([`ROUND_OFF`]: relative for speeds and accelerations, rad
//! for positions). The first failure in time (then axis, then position before velocity before
//! acceleration) is the error.

use super::error::GoalError;
use super::joints::Joints;
use super::plan::{Plan, ROUND_OFF};
use super::quantity::Quantity;
use super::{Sample, within};

/// Check `plan` (see the module doc).
pub fn check(plan: &Plan, joints: &Joints) -> Result<(), GoalError> {
    let times = plan.knot_times();
    let dt = plan.dt();
    for i in 0..times.len().saturating_sub(1) {
        let (t0, t1) = (times[i], times[i + 1]);
        let mut j = (t0 / dt).floor() as usize + 1;
        check_sample(plan, joints, t0, plan.eval(i, 0.0))?;
        while (j as f64) * dt < t1 {
            let t = j as f64 * dt;
            check_sample(plan, joints, t, plan.eval(i, t - t0))?;
            j += 1;
        }
        check_sample(plan, joints, t1, plan.eval(i, t1 - t0))?;
    }
    Ok(())
}

fn check_sample(plan: &Plan, joints: &Joints, t: f64, s: Option<Sample>) -> Result<(), GoalError> {
    let Some(s) = s else { return Ok(()) };
    let time = plan.time_from_start(t);
    for (axis, l) in joints.limits().iter().enumerate() {
        let joint = || joints.name(axis).to_string();
        let p = s.position[axis];
        if !(p >= l.min - ROUND_OFF && p <= l.max + ROUND_OFF) {
            return Err(GoalError::PositionLimit {
                joint: joint(),
                time,
                value: p,
                min: l.min,
                max: l.max,
                pvt: None,
            });
        }
        let rates = [
            (Quantity::Velocity, s.velocity[axis], l.velocity),
            (Quantity::Acceleration, s.acceleration[axis], l.acceleration),
        ];
        for (quantity, value, limit) in rates {
            if !within(value, limit * (1.0 + ROUND_OFF)) {
                return Err(GoalError::Limit {
                    joint: joint(),
                    quantity,
                    time,
                    value,
                    limit,
                    pvt: None,
                });
            }
        }
    }
    Ok(())
}
