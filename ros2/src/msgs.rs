//! The ROS 2 messages the node speaks, as serde structs.
//!
//! ros2-client bundles no message packages: a message is a plain struct whose fields follow the
//! `.msg` definition in order and type (that order and those types decide the CDR encoding on the
//! wire), and whose DDS type name is `pkg::msg::dds_::Name_`. Each module here names the ROS 2
//! package it mirrors; the definitions are the same in every distribution served but for
//! control_msgs' feedback, sent in the served distribution's layout ([`crate::distro`]).
//! `tests/end_to_end/ros2.rs` checks them against the real ROS 2 type support: rclpy (PyPI wheels)
//! talks to the node with every one of them.

pub mod bounded;
pub mod builtin;
pub mod control;
pub mod diagnostic;
pub mod sensor;
pub mod std_msgs;
pub mod std_srvs;
pub mod trajectory;

/// ros2-client sends and receives any type that is marked a [`ros2_client::Message`].
macro_rules! messages {
    ($($t:ty),* $(,)?) => { $(impl ros2_client::Message for $t {})* };
}

messages!(
    std_msgs::StringMsg,
    sensor::JointState,
    trajectory::JointTrajectory,
    control::FollowJointTrajectoryGoal,
    control::FollowJointTrajectoryResult,
    control::FeedbackOnWire,
    diagnostic::DiagnosticArray,
    std_srvs::TriggerRequest,
    std_srvs::TriggerResponse,
);
