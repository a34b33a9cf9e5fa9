//! `std_srvs`: `Trigger`.

use serde::{Deserialize, Serialize};

/// The request of `std_srvs/srv/Trigger`: empty. (An empty ROS 2 message has one placeholder
/// byte on the wire, `structure_needs_at_least_one_member`.)
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct TriggerRequest {
    pub structure_needs_at_least_one_member: u8,
}

/// The response of `std_srvs/srv/Trigger`.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct TriggerResponse {
    pub success: bool,
    pub message: String,
}
