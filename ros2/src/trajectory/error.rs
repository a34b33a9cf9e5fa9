//! Why a goal is refused, with the ROS error code of each reason.

use super::quantity::Quantity;
use crate::msgs::control::error_code;
use mcm_shared::ranges::Num;

/// A goal the plan refuses. Joint names are the ROS names; values are SI and, in the
/// messages, degrees too. `index` is a point's index in the goal's `points` (0-based).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GoalError {
    #[error(
        "joint_names must name each of the arm's joints exactly once ({known}){}{}{}",
        listed("; unknown", unknown),
        listed("; missing", missing),
        listed("; named more than once", duplicate)
    )]
    JointNames {
        unknown: Vec<String>,
        missing: Vec<String>,
        duplicate: Vec<String>,
        known: String,
    },
    #[error(
        "{field} names the joint {name:?}, which the arm does not have; its joints are {known}"
    )]
    ToleranceJoint {
        field: &'static str,
        name: String,
        known: String,
    },
    #[error("the trajectory has no points; it needs at least one")]
    NoPoints,
    #[error("{field} has {len} entries; allowed: at most {max} (docs/ros2.md, limits)")]
    Oversize {
        field: String,
        len: usize,
        max: usize,
    },
    #[error("point {index}: time_from_start {} s is negative; it must be 0 or more", Num(*time))]
    NegativeTime { index: usize, time: f64 },
    #[error(
        "point {index}: time_from_start {} s is not after point {}'s {} s; the times must increase strictly",
        Num(*time), index - 1, Num(*previous)
    )]
    TimeNotIncreasing {
        index: usize,
        time: f64,
        previous: f64,
    },
    #[error("point {index}: {field} has {len} values; it must have {allowed}")]
    Length {
        index: usize,
        field: &'static str,
        len: usize,
        allowed: &'static str,
    },
    #[error("point {index}: {field} of joint {joint:?} is {value}; every value must be finite")]
    NonFinite {
        index: usize,
        field: &'static str,
        joint: String,
        value: f64,
    },
    #[error(
        "point {index}: position of joint {joint:?} {} is outside its reachable range {} to {} (the limits less the safety margin)",
        Quantity::Position.show(*value), Quantity::Position.show(*min), Quantity::Position.show(*max)
    )]
    OutOfRange {
        index: usize,
        joint: String,
        value: f64,
        min: f64,
        max: f64,
    },
    #[error(
        "point 0 (time_from_start 0) is where the trajectory starts, but joint {joint:?} is at {} there and at {} in the arm's start state: {} apart, more than the {} allowed",
        Quantity::Position.show(*position), Quantity::Position.show(*start),
        Quantity::Position.show((position - start).abs()), Quantity::Position.show(*tolerance)
    )]
    StartTooFar {
        joint: String,
        position: f64,
        start: f64,
        tolerance: f64,
    },
    #[error(
        "joint {joint:?} position {} at time_from_start {} s{} is outside its reachable range {} to {} (the limits less the safety margin)",
        Quantity::Position.show(*value), Num(*time), on(*pvt),
        Quantity::Position.show(*min), Quantity::Position.show(*max)
    )]
    PositionLimit {
        joint: String,
        time: f64,
        value: f64,
        min: f64,
        max: f64,
        /// `Some(k)`: found on the core's interpolation towards PVT point `k` (0-based).
        pvt: Option<usize>,
    },
    #[error(
        "joint {joint:?} {quantity} {} at time_from_start {} s{} exceeds the limit {}",
        quantity.show(*value), Num(*time), on(*pvt), quantity.show(*limit)
    )]
    Limit {
        joint: String,
        quantity: Quantity,
        time: f64,
        value: f64,
        limit: f64,
        /// `Some(k)`: found on the core's interpolation towards PVT point `k` (0-based).
        pvt: Option<usize>,
    },
    #[error(
        "the trajectory ends at header.stamp {} s + {} s, {} s before the arm can start it; a stamp must be 0 (start now) or leave the trajectory's end in the future",
        Num(*stamp), Num(*last), Num(*late)
    )]
    OldHeaderTimestamp {
        /// header.stamp [s since the clock's epoch].
        stamp: f64,
        /// The last point's time_from_start [s].
        last: f64,
        /// How long before the plan's start the trajectory ends [s], 0 or more.
        late: f64,
    },
    #[error(
        "the trajectory's only point is its start (time_from_start 0), but joint {joint:?} moves at {} in the start state; give the arm time to stop there",
        Quantity::Velocity.show(*velocity)
    )]
    CannotStop { joint: String, velocity: f64 },
    #[error(
        "{field} of joint {joint:?}: {quantity} {value} is not allowed; a tolerance is -1 (no limit), 0 (the default) or positive"
    )]
    Tolerance {
        field: &'static str,
        joint: String,
        quantity: Quantity,
        value: f64,
    },
    #[error("goal_time_tolerance {} s is not allowed; it must be 0 (the default) or positive", Num(*value))]
    GoalTime { value: f64 },
    #[error("the PVT spacing dt = {} s is not allowed; it must be a positive finite number", Num(*dt))]
    Dt { dt: f64 },
    #[error(
        "the trajectory would end {end:.3} s from now (its stamp plus its last point's time_from_start); at most {max} s"
    )]
    TooLong { end: f64, max: f64 },
    #[error("the start state's {quantity} of joint {joint:?} is {value}; it must be finite")]
    Start {
        joint: String,
        quantity: Quantity,
        value: f64,
    },
}

impl GoalError {
    /// The `error_code` of `FollowJointTrajectory`'s result for this refusal.
    pub fn code(&self) -> i32 {
        match self {
            GoalError::JointNames { .. } | GoalError::ToleranceJoint { .. } => {
                error_code::INVALID_JOINTS
            }
            GoalError::OldHeaderTimestamp { .. } => error_code::OLD_HEADER_TIMESTAMP,
            _ => error_code::INVALID_GOAL,
        }
    }
}

/// "; unknown: \"a\", \"b\"" or nothing for an empty list.
fn listed(label: &str, names: &[String]) -> String {
    if names.is_empty() {
        return String::new();
    }
    let quoted: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    format!("{label}: {}", quoted.join(", "))
}

/// Where a limit was found: on the plan itself, or on the core's interpolation of the PVT
/// points made of it.
fn on(pvt: Option<usize>) -> String {
    match pvt {
        None => String::new(),
        Some(k) => format!(" (as the core interpolates the PVT points, towards point {k})"),
    }
}
