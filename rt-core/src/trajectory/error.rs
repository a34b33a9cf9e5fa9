//! Typed errors of the trajectory module. Constructing and returning them does not allocate, so
//! they may be produced **inside the cycle**; formatting (`Display`) belongs outside it.
//!
//! Axis indices in these errors are 0-based (0..=5); the protocol layer adds 1 for users.

use thiserror::Error;

/// Why a rest-to-rest profile or a joint move could not be planned.
#[derive(Clone, Copy, Debug, PartialEq, Error)]
pub enum PlanError {
    #[error("distance {value} rad is not allowed: it must be a finite number")]
    Distance { value: f64 },
    #[error("{name} limit {value} is not allowed: it must be finite and > 0")]
    Limit { name: &'static str, value: f64 },
    #[error(
        "axis index {axis} (0-based): {name} limit {value} is not allowed: \
         it must be finite, > 0 and at most {max}"
    )]
    AxisLimit {
        axis: usize,
        name: &'static str,
        value: f64,
        max: f64,
    },
    #[error("velocity factor {value} is not allowed: it must be in (0, 1]")]
    VelocityFactor { value: f64 },
    #[error(
        "axis index {axis} (0-based): start position {value} rad is not allowed: it must be finite"
    )]
    Start { axis: usize, value: f64 },
    #[error(
        "axis index {axis} (0-based): target position {value} rad is not allowed: it must be finite"
    )]
    Target { axis: usize, value: f64 },
    #[error(
        "axis index {axis} (0-based): move of {value} rad from start to target is not allowed: \
         it must be a finite number"
    )]
    Delta { axis: usize, value: f64 },
    #[error("axis index {axis} is not allowed: it must be 0..=5")]
    AxisIndex { axis: usize },
    #[error(
        "planned duration {value} s is not allowed: it must be finite \
         (the distance is too large for the limits)"
    )]
    Duration { value: f64 },
    #[error(
        "distance {distance} rad cannot be planned in floating point with these limits \
         (their ratios are too extreme); use limits within a few decades of each other"
    )]
    Numeric { distance: f64 },
}

/// Why a PVT (cubic Hermite) segment was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Error)]
pub enum SegmentError {
    #[error("PVT segment: {name} {value} is not allowed: it must be a finite number")]
    NonFinite { name: &'static str, value: f64 },
    #[error("PVT segment: dt {value} s is not allowed: it must be finite and > 0")]
    Duration { value: f64 },
    #[error(
        "PVT segment: position range [{min}, {max}] rad is not allowed: \
         both ends must be finite with min < max"
    )]
    Range { min: f64, max: f64 },
    #[error("PVT segment: {name} limit {value} is not allowed: it must be finite and > 0")]
    Limit { name: &'static str, value: f64 },
    #[error(
        "PVT segment: position {position} rad at {tau} s into the segment is outside \
         the allowed range [{min}, {max}] rad"
    )]
    Position {
        position: f64,
        tau: f64,
        min: f64,
        max: f64,
    },
    #[error(
        "PVT segment: velocity {velocity} rad/s at {tau} s into the segment exceeds \
         the allowed ±{limit} rad/s"
    )]
    Velocity { velocity: f64, tau: f64, limit: f64 },
    #[error(
        "PVT segment: acceleration {acceleration} rad/s² at {tau} s into the segment exceeds \
         the allowed ±{limit} rad/s²"
    )]
    Acceleration {
        acceleration: f64,
        tau: f64,
        limit: f64,
    },
}

/// A PVT segment of six axes was rejected: which axis, and why.
#[derive(Clone, Copy, Debug, PartialEq, Error)]
#[error("axis index {axis} (0-based): {error}")]
pub struct PvtSegmentError {
    pub axis: usize,
    pub error: SegmentError,
}

/// A batch did not fit into the PVT queue; nothing of it was queued.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Error)]
#[error(
    "PVT queue full: {offered} points offered but only {free} of {capacity} places are free; \
     nothing of this batch was queued"
)]
pub struct QueueFull {
    pub offered: usize,
    pub free: usize,
    pub capacity: usize,
}

/// Why a stop could not be planned as asked (see [`super::StopPlan::try_plan_from_state`]).
#[derive(Clone, Copy, Debug, PartialEq, Error)]
pub enum StopError {
    #[error(
        "axis index {axis} (0-based): {name} {value} is not allowed: it must be a finite number"
    )]
    State {
        axis: usize,
        name: &'static str,
        value: f64,
    },
    #[error(
        "axis index {axis} (0-based): stop deceleration {value} rad/s² is not allowed: \
         it must be finite and > 0"
    )]
    Deceleration { axis: usize, value: f64 },
    #[error(
        "axis index {axis} (0-based): stop jerk {value} rad/s³ is not allowed: \
         it must be finite and > 0 (or none)"
    )]
    Jerk { axis: usize, value: f64 },
}
