//! `sensor_msgs`: `JointState`.

use super::std_msgs::Header;
use serde::{Deserialize, Serialize};

/// `sensor_msgs/msg/JointState`: [rad], [rad/s], [N m], in the order of `name`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct JointState {
    pub header: Header,
    pub name: Vec<String>,
    pub position: Vec<f64>,
    pub velocity: Vec<f64>,
    pub effort: Vec<f64>,
}
