//! The ROS 2 distribution whose peers the node serves (`--ros-distro`), and every difference
//! between the distributions in the messages the node speaks (`docs/ros2.md`, distributions).
//!
//! One build serves Jazzy, Kilted and Lyrical: their DDS wire format is the same (16-byte GUIDs
//! in `ros_discovery_info`, the same topic and type names), and of the node's messages only
//! control_msgs' `FollowJointTrajectory` feedback differs ([`RosDistro::feedback_has_index`]).
//! Humble (24-byte GUIDs) would need ros2-client built with its `humble` feature.

use std::fmt;

/// A ROS 2 distribution this build serves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RosDistro {
    /// Jazzy Jalisco (LTS, to May 2029): control_msgs 5.x.
    Jazzy,
    /// Kilted Kaiju (to 2026-12-31): control_msgs 6.x.
    Kilted,
    /// Lyrical Luth (LTS, from May 2026): control_msgs from its `master` branch, 6.x.
    Lyrical,
}

/// A distribution name this build does not serve.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "ROS 2 distribution {value:?} is not served by this build; allowed: jazzy, kilted, lyrical{hint}"
)]
pub struct UnknownDistro {
    pub value: String,
    hint: &'static str,
}

impl RosDistro {
    /// Every distribution served, oldest first.
    pub const ALL: [RosDistro; 3] = [RosDistro::Jazzy, RosDistro::Kilted, RosDistro::Lyrical];

    /// The default without `--ros-distro` or a known `ROS_DISTRO`: the long-term release.
    pub const DEFAULT: RosDistro = RosDistro::Jazzy;

    /// Its name as `ROS_DISTRO` spells it.
    pub const fn name(self) -> &'static str {
        match self {
            RosDistro::Jazzy => "jazzy",
            RosDistro::Kilted => "kilted",
            RosDistro::Lyrical => "lyrical",
        }
    }

    /// The distribution named `value` (as `ROS_DISTRO` spells it).
    pub fn parse(value: &str) -> Result<RosDistro, UnknownDistro> {
        Self::ALL
            .into_iter()
            .find(|d| d.name() == value)
            .ok_or_else(|| UnknownDistro {
                value: value.to_string(),
                hint: match value {
                    "humble" | "galactic" => {
                        " (Humble and older put 24-byte GUIDs in ros_discovery_info, this build \
                         16: docs/ros2.md, distributions)"
                    }
                    _ => "",
                },
            })
    }

    /// The distribution when `--ros-distro` is not given: `ros_distro_env` (`ROS_DISTRO`) when
    /// it names one served, else [`RosDistro::DEFAULT`]; with the reason for a value not used.
    pub fn from_env(ros_distro_env: Option<&str>) -> (RosDistro, Option<UnknownDistro>) {
        match ros_distro_env.map(str::trim).filter(|v| !v.is_empty()) {
            None => (Self::DEFAULT, None),
            Some(v) => match Self::parse(v) {
                Ok(d) => (d, None),
                Err(e) => (Self::DEFAULT, Some(e)),
            },
        }
    }

    /// Whether control_msgs' `FollowJointTrajectory` feedback has `int32 index` after `error`
    /// and `int32 multi_dof_index` at its end (control_msgs 6.x, from 6.3.0: Kilted, Lyrical);
    /// control_msgs 5.x (Jazzy) and 4.x (Humble) have neither. Goal and result are the same in
    /// all of them.
    pub const fn feedback_has_index(self) -> bool {
        match self {
            RosDistro::Jazzy => false,
            RosDistro::Kilted | RosDistro::Lyrical => true,
        }
    }
}

impl fmt::Display for RosDistro {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for RosDistro {
    type Err = UnknownDistro;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::parse(s)
    }
}

#[cfg(test)]
mod tests;
