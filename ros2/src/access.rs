//! What the node offers over DDS: every interface, or, with `--ros2-read-only`, only those that
//! read the arm. DDS has no notion of who is asking, so what the node offers is what anyone on
//! its domain can do (docs/security.md).

use crate::motion::ServiceKind;

/// Which interfaces the node offers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// The arm is read and moved: joint states, the robot description and the diagnostics; the
    /// `follow_joint_trajectory` action, the `joint_trajectory` topic, the services (each sends
    /// the core a command) and ROS 2's parameter services.
    Motion,
    /// The arm is only read: joint states, the robot description and the diagnostics. Nothing
    /// that sends the core a command (so the node never holds control of the arm), and no
    /// parameter services (`set_parameters` writes).
    ReadOnly,
}

impl Access {
    /// `--ros2-read-only` given or not.
    pub fn from_read_only(read_only: bool) -> Access {
        if read_only {
            Access::ReadOnly
        } else {
            Access::Motion
        }
    }

    /// Whether the motion interface is offered.
    pub fn offers_motion(self) -> bool {
        self == Access::Motion
    }

    /// What `/diagnostics` says under "motion interface".
    pub fn diagnostics_value(self) -> &'static str {
        match self {
            Access::Motion => "offered",
            Access::ReadOnly => "none (--ros2-read-only)",
        }
    }

    /// The node's line at start: which interfaces it offers (their names under its namespace,
    /// as docs/ros2.md lists them) and, read-only, which not.
    pub fn start_line(self) -> String {
        let reading = "joint_states, robot_description, /diagnostics";
        let motion = format!(
            "follow_joint_trajectory, joint_trajectory, the services {} and the parameter services",
            ServiceKind::ALL.map(ServiceKind::name).join(", ")
        );
        match self {
            Access::Motion => format!("mcm-ros2: offering {reading}, {motion}"),
            Access::ReadOnly => format!(
                "mcm-ros2: read-only (--ros2-read-only): offering {reading}; no motion \
                 interface: none of {motion}"
            ),
        }
    }
}

#[cfg(test)]
mod tests;
