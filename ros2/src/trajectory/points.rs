//! A goal's points checked one by one and put in axis order.

use super::error::GoalError;
use super::joints::Joints;
use super::order::ColumnOrder;
use crate::msgs::trajectory::JointTrajectory;
use mcm_shared::NUM_AXES;

/// One point of the goal (rad, rad/s, rad/s², axis order); `effort` is not used.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GoalPoint {
    /// Its index in the goal's `points`.
    pub index: usize,
    /// `time_from_start` [s].
    pub time: f64,
    pub position: [f64; NUM_AXES],
    pub velocity: Option<[f64; NUM_AXES]>,
    pub acceleration: Option<[f64; NUM_AXES]>,
}

/// The points of `traj`, each checked: times 0 or more and strictly increasing, positions
/// with one value per joint, velocities and accelerations with none or one per joint, every
/// value finite, every position in its joint's reachable range.
pub fn goal_points(
    traj: &JointTrajectory,
    order: &ColumnOrder,
    joints: &Joints,
) -> Result<Vec<GoalPoint>, GoalError> {
    super::size::check_trajectory_size(traj)?;
    if traj.points.is_empty() {
        return Err(GoalError::NoPoints);
    }
    let mut out: Vec<GoalPoint> = Vec::with_capacity(traj.points.len());
    for (index, p) in traj.points.iter().enumerate() {
        let time = p.time_from_start.as_secs_f64();
        if time < 0.0 {
            return Err(GoalError::NegativeTime { index, time });
        }
        if let Some(prev) = out.last()
            && time <= prev.time
        {
            return Err(GoalError::TimeNotIncreasing {
                index,
                time,
                previous: prev.time,
            });
        }
        let column = |field: &'static str, values: &[f64], optional: bool| {
            vector(traj, index, field, values, optional).map(|v| v.map(|v| order.axis_values(v)))
        };
        let position = column("positions", &p.positions, false)?.unwrap_or_default();
        let velocity = column("velocities", &p.velocities, true)?;
        let acceleration = column("accelerations", &p.accelerations, true)?;
        for (axis, l) in joints.limits().iter().enumerate() {
            let value = position[axis];
            if !(value >= l.min && value <= l.max) {
                return Err(GoalError::OutOfRange {
                    index,
                    joint: joints.name(axis).to_string(),
                    value,
                    min: l.min,
                    max: l.max,
                });
            }
        }
        out.push(GoalPoint {
            index,
            time,
            position,
            velocity,
            acceleration,
        });
    }
    Ok(out)
}

/// `values` checked: one per joint (or none if `optional`), all finite. `None` when empty.
fn vector<'a>(
    traj: &JointTrajectory,
    index: usize,
    field: &'static str,
    values: &'a [f64],
    optional: bool,
) -> Result<Option<&'a [f64]>, GoalError> {
    if optional && values.is_empty() {
        return Ok(None);
    }
    if values.len() != NUM_AXES {
        return Err(GoalError::Length {
            index,
            field,
            len: values.len(),
            allowed: if optional {
                "none or one per joint (6)"
            } else {
                "one per joint (6)"
            },
        });
    }
    if let Some((c, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(GoalError::NonFinite {
            index,
            field,
            joint: traj.joint_names[c].clone(),
            value,
        });
    }
    Ok(Some(values))
}
