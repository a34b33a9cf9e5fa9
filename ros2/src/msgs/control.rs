//! `control_msgs`: the `FollowJointTrajectory` action of ros2_control's joint trajectory
//! controller (control_msgs 6.x, ROS 2 Kilted: the feedback carries the point `index`).

use super::bounded::Bounded;
use super::builtin::Duration;
use super::std_msgs::Header;
use super::trajectory::{
    JointTrajectory, JointTrajectoryPoint, MultiDofJointTrajectory, MultiDofJointTrajectoryPoint,
};
use crate::trajectory::MAX_JOINTS;
use serde::{Deserialize, Serialize};

/// `control_msgs/msg/JointTolerance`: 0 = the default, -1 = no limit.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct JointTolerance {
    pub name: String,
    pub position: f64,
    pub velocity: f64,
    pub acceleration: f64,
}

/// `control_msgs/msg/JointComponentTolerance` (for multi-DOF joints; this arm has none).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct JointComponentTolerance {
    pub joint_name: String,
    pub component: u16,
    pub position: f64,
    pub velocity: f64,
    pub acceleration: f64,
}

/// The goal of `control_msgs/action/FollowJointTrajectory`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct FollowJointTrajectoryGoal {
    pub trajectory: JointTrajectory,
    pub multi_dof_trajectory: MultiDofJointTrajectory,
    pub path_tolerance: Bounded<JointTolerance, MAX_JOINTS>,
    pub component_path_tolerance: Bounded<JointComponentTolerance, MAX_JOINTS>,
    pub goal_tolerance: Bounded<JointTolerance, MAX_JOINTS>,
    pub component_goal_tolerance: Bounded<JointComponentTolerance, MAX_JOINTS>,
    pub goal_time_tolerance: Duration,
}

/// The result's `error_code` values.
pub mod error_code {
    pub const SUCCESSFUL: i32 = 0;
    pub const INVALID_GOAL: i32 = -1;
    pub const INVALID_JOINTS: i32 = -2;
    pub const OLD_HEADER_TIMESTAMP: i32 = -3;
    pub const PATH_TOLERANCE_VIOLATED: i32 = -4;
    pub const GOAL_TOLERANCE_VIOLATED: i32 = -5;
}

/// The result of `control_msgs/action/FollowJointTrajectory`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct FollowJointTrajectoryResult {
    pub error_code: i32,
    pub error_string: String,
}

/// The feedback of `control_msgs/action/FollowJointTrajectory`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct FollowJointTrajectoryFeedback {
    pub header: Header,
    pub joint_names: Vec<String>,
    pub desired: JointTrajectoryPoint,
    pub actual: JointTrajectoryPoint,
    pub error: JointTrajectoryPoint,
    /// The index of the trajectory point being executed.
    pub index: i32,
    pub multi_dof_joint_names: Vec<String>,
    pub multi_dof_desired: MultiDofJointTrajectoryPoint,
    pub multi_dof_actual: MultiDofJointTrajectoryPoint,
    pub multi_dof_error: MultiDofJointTrajectoryPoint,
    pub multi_dof_index: i32,
}
