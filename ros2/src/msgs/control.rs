//! `control_msgs`: the `FollowJointTrajectory` action of ros2_control's joint trajectory
//! controller. Goal and result are the same in every distribution; the feedback's layout is the
//! served distribution's ([`FeedbackOnWire`], [`RosDistro::feedback_has_index`]).

use super::bounded::Bounded;
use super::builtin::Duration;
use super::std_msgs::Header;
use super::trajectory::{
    JointTrajectory, JointTrajectoryPoint, MultiDofJointTrajectory, MultiDofJointTrajectoryPoint,
};
use crate::distro::RosDistro;
use crate::trajectory::MAX_JOINTS;
use serde::ser::SerializeStruct;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

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

/// The feedback of `control_msgs/action/FollowJointTrajectory`, with every field of any
/// distribution; [`FeedbackOnWire`] sends the served distribution's.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FollowJointTrajectoryFeedback {
    pub header: Header,
    pub joint_names: Vec<String>,
    pub desired: JointTrajectoryPoint,
    pub actual: JointTrajectoryPoint,
    pub error: JointTrajectoryPoint,
    /// The index of the trajectory point being executed (control_msgs 6.x only).
    pub index: i32,
    pub multi_dof_joint_names: Vec<String>,
    pub multi_dof_desired: MultiDofJointTrajectoryPoint,
    pub multi_dof_actual: MultiDofJointTrajectoryPoint,
    pub multi_dof_error: MultiDofJointTrajectoryPoint,
    /// control_msgs 6.x only.
    pub multi_dof_index: i32,
}

/// The feedback as the peers of `distro` decode it: control_msgs 6.x's fields with `index` and
/// `multi_dof_index`, or 5.x's without them. The node publishes feedback and never reads it.
#[derive(Debug, Clone, PartialEq)]
pub struct FeedbackOnWire {
    pub distro: RosDistro,
    pub feedback: FollowJointTrajectoryFeedback,
}

impl Serialize for FeedbackOnWire {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let f = &self.feedback;
        let index = self.distro.feedback_has_index();
        let mut s = serializer
            .serialize_struct("FollowJointTrajectory_Feedback", if index { 11 } else { 9 })?;
        s.serialize_field("header", &f.header)?;
        s.serialize_field("joint_names", &f.joint_names)?;
        s.serialize_field("desired", &f.desired)?;
        s.serialize_field("actual", &f.actual)?;
        s.serialize_field("error", &f.error)?;
        if index {
            s.serialize_field("index", &f.index)?;
        }
        s.serialize_field("multi_dof_joint_names", &f.multi_dof_joint_names)?;
        s.serialize_field("multi_dof_desired", &f.multi_dof_desired)?;
        s.serialize_field("multi_dof_actual", &f.multi_dof_actual)?;
        s.serialize_field("multi_dof_error", &f.multi_dof_error)?;
        if index {
            s.serialize_field("multi_dof_index", &f.multi_dof_index)?;
        }
        s.end()
    }
}

/// ros2-client's messages must decode too; the node never reads feedback, and its bytes do not
/// say which distribution's layout they are in.
impl<'de> Deserialize<'de> for FeedbackOnWire {
    fn deserialize<D: Deserializer<'de>>(_: D) -> Result<Self, D::Error> {
        Err(serde::de::Error::custom(
            "the node does not read FollowJointTrajectory feedback: its layout depends on the \
             ROS 2 distribution (--ros-distro)",
        ))
    }
}

#[cfg(test)]
mod tests;
