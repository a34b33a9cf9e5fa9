//! A goal's tolerances (control_msgs/JointTolerance) and the checks of the arm's state against
//! them while the trajectory runs (path) and at its end (goal).
//!
//! Per joint and quantity a tolerance is: 0, the default ([`ToleranceDefaults`]); -1, no
//! limit; a positive value, that bound on |actual - desired|. Any other value is refused
//! (INVALID_GOAL); a tolerance naming a joint the arm does not have is refused as
//! INVALID_JOINTS, and so is any multi-DOF (component) tolerance, since the arm has no
//! multi-DOF joint. A joint named twice takes its last entry. Acceleration tolerances are
//! parsed and kept but not checked: the checks take no measured acceleration.

use super::error::GoalError;
use super::joints::Joints;
use super::quantity::Quantity;
use super::{Sample, within};
use crate::msgs::control::{FollowJointTrajectoryGoal, JointTolerance, error_code};
use mcm_shared::NUM_AXES;

/// The tolerances a goal leaves at 0 (`None`: no limit). SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToleranceDefaults {
    pub path_position: Option<f64>,
    pub path_velocity: Option<f64>,
    pub path_acceleration: Option<f64>,
    pub goal_position: Option<f64>,
    pub goal_velocity: Option<f64>,
    pub goal_acceleration: Option<f64>,
    /// How long after the trajectory's end the goal tolerances may take to be met [s].
    pub goal_time: f64,
}

impl Default for ToleranceDefaults {
    /// Path: 0.05 rad (2.9 deg) of position error, speed unchecked. Goal: 0.01 rad (0.57 deg)
    /// of position and 0.01 rad/s of speed (the arm has stopped: ros2_control's default
    /// `stopped_velocity_tolerance`), within 0.5 s of the end.
    fn default() -> Self {
        ToleranceDefaults {
            path_position: Some(0.05),
            path_velocity: None,
            path_acceleration: None,
            goal_position: Some(0.01),
            goal_velocity: Some(0.01),
            goal_acceleration: None,
            goal_time: 0.5,
        }
    }
}

/// One joint's bounds on |actual - desired| (`None`: no limit).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Bounds {
    pub position: Option<f64>,
    pub velocity: Option<f64>,
    pub acceleration: Option<f64>,
}

/// The tolerances of one goal, per axis (axis order).
#[derive(Debug, Clone, PartialEq)]
pub struct Tolerances {
    path: [Bounds; NUM_AXES],
    goal: [Bounds; NUM_AXES],
    goal_time: f64,
    names: [String; NUM_AXES],
}

/// Which tolerance was violated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    Path,
    Goal,
}

/// The arm's state is outside a tolerance: joint, quantity, error (actual - desired, SI) and
/// the tolerance.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "{} tolerance violated: joint {joint:?} {quantity} error {} exceeds the tolerance {}",
    match phase { Phase::Path => "path", Phase::Goal => "goal" },
    quantity.show(*error), quantity.show(*tolerance)
)]
pub struct Violation {
    pub phase: Phase,
    pub joint: String,
    pub quantity: Quantity,
    pub error: f64,
    pub tolerance: f64,
}

impl Violation {
    /// The result's `error_code`: PATH_ or GOAL_TOLERANCE_VIOLATED.
    pub fn code(&self) -> i32 {
        match self.phase {
            Phase::Path => error_code::PATH_TOLERANCE_VIOLATED,
            Phase::Goal => error_code::GOAL_TOLERANCE_VIOLATED,
        }
    }
}

impl Tolerances {
    /// The tolerances of `goal` for the arm `joints`, with `defaults` where the goal says 0.
    pub fn from_goal(
        goal: &FollowJointTrajectoryGoal,
        joints: &Joints,
        defaults: &ToleranceDefaults,
    ) -> Result<Tolerances, GoalError> {
        let components = [
            ("component_path_tolerance", &goal.component_path_tolerance),
            ("component_goal_tolerance", &goal.component_goal_tolerance),
        ];
        for (field, list) in components {
            if let Some(c) = list.first() {
                return Err(GoalError::ToleranceJoint {
                    field,
                    name: c.joint_name.clone(),
                    known: format!("{} (none of them multi-DOF)", joints.known()),
                });
            }
        }
        let path_defaults = Bounds {
            position: defaults.path_position,
            velocity: defaults.path_velocity,
            acceleration: defaults.path_acceleration,
        };
        let goal_defaults = Bounds {
            position: defaults.goal_position,
            velocity: defaults.goal_velocity,
            acceleration: defaults.goal_acceleration,
        };
        let goal_time = goal.goal_time_tolerance.as_secs_f64();
        let goal_time = match goal_time {
            0.0 => defaults.goal_time,
            t if t > 0.0 => t,
            value => return Err(GoalError::GoalTime { value }),
        };
        Ok(Tolerances {
            path: per_axis(
                "path_tolerance",
                &goal.path_tolerance,
                joints,
                path_defaults,
            )?,
            goal: per_axis(
                "goal_tolerance",
                &goal.goal_tolerance,
                joints,
                goal_defaults,
            )?,
            goal_time,
            names: joints.names().clone(),
        })
    }

    /// The path bounds of axis `axis` (0-based).
    pub fn path(&self, axis: usize) -> Bounds {
        self.path[axis]
    }

    /// The goal bounds of axis `axis` (0-based).
    pub fn goal(&self, axis: usize) -> Bounds {
        self.goal[axis]
    }

    /// How long after the trajectory's end the goal tolerances may take to be met [s].
    pub fn goal_time(&self) -> f64 {
        self.goal_time
    }

    /// The arm's state (rad, rad/s, axis order) against the path tolerances around the plan's
    /// `desired` state; the first axis out of tolerance, position before velocity.
    pub fn check_path(
        &self,
        desired: &Sample,
        actual_pos: &[f64; NUM_AXES],
        actual_vel: &[f64; NUM_AXES],
    ) -> Result<(), Violation> {
        self.check(Phase::Path, &self.path, desired, actual_pos, actual_vel)
    }

    /// The arm's state against the goal tolerances around the plan's final state.
    pub fn check_goal(
        &self,
        final_state: &Sample,
        actual_pos: &[f64; NUM_AXES],
        actual_vel: &[f64; NUM_AXES],
    ) -> Result<(), Violation> {
        self.check(Phase::Goal, &self.goal, final_state, actual_pos, actual_vel)
    }

    fn check(
        &self,
        phase: Phase,
        bounds: &[Bounds; NUM_AXES],
        desired: &Sample,
        actual_pos: &[f64; NUM_AXES],
        actual_vel: &[f64; NUM_AXES],
    ) -> Result<(), Violation> {
        for (axis, b) in bounds.iter().enumerate() {
            let checks = [
                (
                    Quantity::Position,
                    b.position,
                    actual_pos[axis] - desired.position[axis],
                ),
                (
                    Quantity::Velocity,
                    b.velocity,
                    actual_vel[axis] - desired.velocity[axis],
                ),
            ];
            for (quantity, bound, error) in checks {
                if let Some(tolerance) = bound
                    && !within(error, tolerance)
                {
                    return Err(Violation {
                        phase,
                        joint: self.names[axis].clone(),
                        quantity,
                        error,
                        tolerance,
                    });
                }
            }
        }
        Ok(())
    }
}

/// The bounds of every axis from a goal's list `field`.
fn per_axis(
    field: &'static str,
    list: &[JointTolerance],
    joints: &Joints,
    defaults: Bounds,
) -> Result<[Bounds; NUM_AXES], GoalError> {
    let mut out = [defaults; NUM_AXES];
    for t in list {
        let axis = joints
            .axis_of(&t.name)
            .ok_or_else(|| GoalError::ToleranceJoint {
                field,
                name: t.name.clone(),
                known: joints.known(),
            })?;
        let one = |quantity: Quantity, value: f64, default: Option<f64>| match value {
            0.0 => Ok(default),
            -1.0 => Ok(None),
            v if v > 0.0 && v.is_finite() => Ok(Some(v)),
            value => Err(GoalError::Tolerance {
                field,
                joint: t.name.clone(),
                quantity,
                value,
            }),
        };
        out[axis] = Bounds {
            position: one(Quantity::Position, t.position, defaults.position)?,
            velocity: one(Quantity::Velocity, t.velocity, defaults.velocity)?,
            acceleration: one(
                Quantity::Acceleration,
                t.acceleration,
                defaults.acceleration,
            )?,
        };
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
