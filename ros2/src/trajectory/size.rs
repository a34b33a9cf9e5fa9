//! The largest goal the node takes: checked first, on the lengths as sent (a sequence over its
//! limit was read without keeping its elements, `crate::msgs::bounded`).

use super::error::GoalError;
use crate::msgs::control::FollowJointTrajectoryGoal;
use crate::msgs::trajectory::JointTrajectory;

/// The most points a trajectory may have. The node checks every point and plans through them
/// at the cycle rate; the core takes the plan one cycle's point at a time in batches, whatever
/// the goal's point count. So points denser than the cycle (5 ms) add nothing, and 10,000 is
/// one point per cycle for 50 s, or one every 60 ms over the longest trajectory
/// ([`super::MAX_DURATION_S`], 600 s): far above what MoveIt sends (tens to hundreds). A goal's
/// points take about 250 bytes each in the node: 2.5 MB at the limit.
pub const MAX_POINTS: usize = 10_000;

/// The most entries of the per-joint sequences: joint names, a point's positions, velocities,
/// accelerations and efforts, the tolerances. The arm has six joints; a longer sequence is
/// refused anyway, by name where it is short enough to name its entries.
pub const MAX_JOINTS: usize = 64;

/// `len` within `max`; else the error naming `field`.
fn within(field: &str, len: usize, max: usize) -> Result<(), GoalError> {
    if len > max {
        return Err(GoalError::Oversize {
            field: field.to_string(),
            len,
            max,
        });
    }
    Ok(())
}

/// The trajectory's lists within their limits (checked again by the plan, which never sees an
/// oversize list: its elements were not kept).
pub fn check_trajectory_size(t: &JointTrajectory) -> Result<(), GoalError> {
    within("trajectory.points", t.points.len(), MAX_POINTS)?;
    within("trajectory.joint_names", t.joint_names.len(), MAX_JOINTS)?;
    for (i, p) in t.points.iter().enumerate() {
        for (f, len) in [
            ("positions", p.positions.len()),
            ("velocities", p.velocities.len()),
            ("accelerations", p.accelerations.len()),
            ("effort", p.effort.len()),
        ] {
            within(&format!("trajectory.points[{i}].{f}"), len, MAX_JOINTS)?;
        }
    }
    Ok(())
}

/// The goal's lists within their limits: else which one, its length and the limit.
pub fn check_size(goal: &FollowJointTrajectoryGoal) -> Result<(), GoalError> {
    check_trajectory_size(&goal.trajectory)?;
    for (f, len) in [
        (
            "multi_dof_trajectory.joint_names",
            goal.multi_dof_trajectory.joint_names.len(),
        ),
        ("path_tolerance", goal.path_tolerance.len()),
        ("goal_tolerance", goal.goal_tolerance.len()),
        (
            "component_path_tolerance",
            goal.component_path_tolerance.len(),
        ),
        (
            "component_goal_tolerance",
            goal.component_goal_tolerance.len(),
        ),
    ] {
        within(f, len, MAX_JOINTS)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests;
