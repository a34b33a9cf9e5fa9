//! Planning of `FollowJointTrajectory` goals for the MCM's PVT stream: pure functions over
//! plain data, no I/O, no clock (the caller passes the time).
//!
//! The node executes a ROS trajectory (ros2_control's joint trajectory controller semantics) as
//! a PVT stream (docs/protocol.md, "pvt_points"): points spaced by a fixed `dt`, the first
//! reached `dt` after the stream starts from its start state, each interpolated by the core as
//! a cubic Hermite spline. This module
//!
//! - maps the goal's joint names onto the arm's axes ([`Joints`]) and validates the goal
//!   ([`GoalError`], carrying the ROS error code);
//! - builds a [`Plan`]: a C1 spline (C2 where the goal gives accelerations) from the start
//!   state through the goal's points, checked against the axis limits both as sampled and as
//!   the core will check the PVT points made of it, and cut into PVT points
//!   ([`Plan::pvt_point`], degrees);
//! - parses the goal's tolerances ([`Tolerances`]) and checks the arm's state against them
//!   ([`Violation`]).
//!
//! All ROS-side values are SI (rad, rad/s, rad/s², s), in the arm's axis order (axis 1 first)
//! unless they are a message's own vectors; PVT points are degrees, as the core takes them.

mod error;
mod joints;
mod knots;
mod limits;
mod order;
mod plan;
mod points;
mod polynomial;
mod quantity;
mod size;
mod stream_check;
mod tolerances;
mod velocities;

pub use error::GoalError;
pub use joints::{AxisCountError, AxisLimits, Joints};
pub use plan::Plan;
pub use quantity::Quantity;
pub use size::{MAX_JOINTS, MAX_POINTS, check_size};
pub use tolerances::{Bounds, Phase, ToleranceDefaults, Tolerances, Violation};

use mcm_shared::NUM_AXES;

/// How far (rad, on every joint) a goal's first point may lie from the start state when its
/// `time_from_start` is 0: such a point says "the trajectory starts here", and the plan starts
/// from the start state instead (as ros2_control's joint trajectory controller does).
pub const START_TOLERANCE_RAD: f64 = 0.01;

/// The longest trajectory, from now to its end [s]. A plan is checked at every cycle of its
/// path in the node's loop before it starts: a 600 s plan at 5 ms took 48 to 61 ms here (three
/// runs, the workspace's optimised dev build), during which the loop misses about ten cycles'
/// joint states.
pub const MAX_DURATION_S: f64 = 600.0;

/// Where the plan joins the stream (rad, rad/s, axis order): the commanded state at the end of
/// what is already queued, or the commanded position at rest when nothing is.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StartState {
    pub position: [f64; NUM_AXES],
    pub velocity: [f64; NUM_AXES],
}

/// The plan's state at one time (rad, rad/s, rad/s², axis order).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    pub position: [f64; NUM_AXES],
    pub velocity: [f64; NUM_AXES],
    pub acceleration: [f64; NUM_AXES],
}

/// |x| <= bound; false for NaN.
fn within(x: f64, bound: f64) -> bool {
    x.abs() <= bound
}

#[cfg(test)]
mod tests;
