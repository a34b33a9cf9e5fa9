//! The knots of a plan: the start state at t = 0, then the goal's points at their times on the
//! plan's clock.
//!
//! The plan's clock starts (t = 0) when the stream reaches the start state. A goal point's time
//! is `offset + time_from_start`, where `offset` is 0 for a zero `header.stamp` ("start now")
//! and otherwise `header.stamp` less the ROS time at t = 0:
//!
//! - a future stamp (offset > 0) holds the start state until the stamp: a knot at t = offset
//!   with the start position at rest (from a moving start, the first segment therefore returns
//!   to the start position by the stamp, within the limits or refused by them);
//! - a past stamp (offset < 0) drops the points whose time is not after t = 0: the path goes
//!   from the start state straight to the first point still ahead, at its time;
//! - a first point with `time_from_start` 0 is the trajectory's start: it must lie within
//!   [`START_TOLERANCE_RAD`] of the start position on every joint, and the start state (or the
//!   hold knot) takes its place. Its accelerations, if given, are kept at t = 0 (when offset
//!   is 0) so that a quintic trajectory stays quintic.

use super::error::GoalError;
use super::joints::Joints;
use super::points::GoalPoint;
use super::{START_TOLERANCE_RAD, StartState, within};
use crate::msgs::builtin::Time;
use mcm_shared::NUM_AXES;

/// A knot before the velocities are estimated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Knot {
    /// On the plan's clock [s].
    pub time: f64,
    pub position: [f64; NUM_AXES],
    pub velocity: Option<[f64; NUM_AXES]>,
    pub acceleration: Option<[f64; NUM_AXES]>,
}

/// The knots of `points` after `start` (see the module doc). `offset` is the plan time of the
/// goal's `time_from_start` 0.
pub fn knots(
    points: &[GoalPoint],
    start: &StartState,
    offset: f64,
    joints: &Joints,
) -> Result<Vec<Knot>, GoalError> {
    let first = &points[0];
    let starts_here = first.time == 0.0;
    if starts_here {
        for axis in 0..NUM_AXES {
            let (position, at) = (first.position[axis], start.position[axis]);
            if !within(position - at, START_TOLERANCE_RAD) {
                return Err(GoalError::StartTooFar {
                    joint: joints.name(axis).to_string(),
                    position,
                    start: at,
                    tolerance: START_TOLERANCE_RAD,
                });
            }
        }
    }
    let mut out = vec![Knot {
        time: 0.0,
        position: start.position,
        velocity: Some(start.velocity),
        acceleration: if starts_here && offset == 0.0 {
            first.acceleration
        } else {
            None
        },
    }];
    if offset > 0.0 {
        out.push(Knot {
            time: offset,
            position: start.position,
            velocity: Some([0.0; NUM_AXES]),
            acceleration: Some([0.0; NUM_AXES]),
        });
    }
    let skip = usize::from(starts_here);
    for p in &points[skip..] {
        let time = offset + p.time;
        if time > out[out.len() - 1].time {
            out.push(Knot {
                time,
                position: p.position,
                velocity: p.velocity,
                acceleration: p.acceleration,
            });
        }
    }
    Ok(out)
}

/// `a - b` in seconds.
pub fn seconds_between(a: Time, b: Time) -> f64 {
    (a.as_nanos() - b.as_nanos()) as f64 * 1e-9
}

/// `t` in seconds since the clock's epoch.
pub fn seconds(t: Time) -> f64 {
    f64::from(t.sec) + f64::from(t.nanosec) * 1e-9
}
