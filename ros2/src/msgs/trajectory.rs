//! `trajectory_msgs`: joint trajectories (and the multi-DOF ones, which the action carries but
//! this arm has no joint for).

use super::bounded::Bounded;
use super::builtin::Duration;
use super::std_msgs::Header;
use crate::trajectory::{MAX_JOINTS, MAX_POINTS};
use serde::{Deserialize, Serialize};

/// `trajectory_msgs/msg/JointTrajectoryPoint`: each vector empty or one value per joint. Every
/// sequence a peer sends is [`Bounded`]: read, but kept only up to the node's limits.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct JointTrajectoryPoint {
    pub positions: Bounded<f64, MAX_JOINTS>,
    pub velocities: Bounded<f64, MAX_JOINTS>,
    pub accelerations: Bounded<f64, MAX_JOINTS>,
    pub effort: Bounded<f64, MAX_JOINTS>,
    pub time_from_start: Duration,
}

/// `trajectory_msgs/msg/JointTrajectory`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct JointTrajectory {
    pub header: Header,
    pub joint_names: Bounded<String, MAX_JOINTS>,
    pub points: Bounded<JointTrajectoryPoint, MAX_POINTS>,
}

/// `geometry_msgs/msg/Vector3`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// `geometry_msgs/msg/Quaternion`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}

/// `geometry_msgs/msg/Transform`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Transform {
    pub translation: Vector3,
    pub rotation: Quaternion,
}

/// `geometry_msgs/msg/Twist`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Twist {
    pub linear: Vector3,
    pub angular: Vector3,
}

/// `trajectory_msgs/msg/MultiDOFJointTrajectoryPoint`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct MultiDofJointTrajectoryPoint {
    pub transforms: Vec<Transform>,
    pub velocities: Vec<Twist>,
    pub accelerations: Vec<Twist>,
    pub time_from_start: Duration,
}

/// `trajectory_msgs/msg/MultiDOFJointTrajectory`. The arm has no multi-DOF joint: a goal with
/// any is refused, so none of its points is kept.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct MultiDofJointTrajectory {
    pub header: Header,
    pub joint_names: Bounded<String, MAX_JOINTS>,
    pub points: Bounded<MultiDofJointTrajectoryPoint, 0>,
}
