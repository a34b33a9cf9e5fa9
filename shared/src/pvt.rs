//! The checks of a PVT point that need nothing but the configuration: position within the
//! reachable range (the software limits less the safety margin) and speed within the axis's
//! limit. The real-time core runs them on every point of a `pvt_points` batch before queueing
//! it; the gateway runs the same function on the whole batch before sending any of it, so a
//! batch the core would refuse for a point costs the core nothing.
//!
//! Pure, allocation-free and panic-free: usable inside the real-time cycle.

use crate::NUM_AXES;
use crate::config::RobotConfig;
use crate::reply::PvtQuantity;

/// The per-point limits of every axis (rad, rad/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLimits {
    /// The range a point's position may lie in: the software limits less the safety margin.
    pub reach_min: [f64; NUM_AXES],
    pub reach_max: [f64; NUM_AXES],
    /// Largest speed of a point.
    pub velocity: [f64; NUM_AXES],
}

impl PointLimits {
    /// The limits of `cfg`, computed exactly as the real-time core's joint parameters are
    /// (the reachable range of [`crate::ranges::reachable_deg`]).
    pub fn from_config(cfg: &RobotConfig) -> PointLimits {
        let a = &cfg.axes;
        let reach = |i| crate::ranges::reachable_deg(cfg, i);
        PointLimits {
            reach_min: core::array::from_fn(|i| reach(i).0.to_radians()),
            reach_max: core::array::from_fn(|i| reach(i).1.to_radians()),
            velocity: core::array::from_fn(|i| a[i].max_velocity_deg_s.to_radians()),
        }
    }
}

/// A point breaks a limit: axis (0-based), which quantity, its value and the limit (rad,
/// rad/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointViolation {
    pub axis: usize,
    pub what: PvtQuantity,
    pub value: f64,
    pub limit: f64,
}

/// Check one point (rad, rad/s): every position finite and reachable, every speed finite and
/// within the limit. The first axis that breaks a limit is reported, position before speed.
pub fn check_point(
    position: &[f64; NUM_AXES],
    velocity: &[f64; NUM_AXES],
    l: &PointLimits,
) -> Result<(), PointViolation> {
    for axis in 0..NUM_AXES {
        let q = position[axis];
        if !(q.is_finite() && q >= l.reach_min[axis] && q <= l.reach_max[axis]) {
            let limit = if q > l.reach_max[axis] {
                l.reach_max[axis]
            } else {
                l.reach_min[axis]
            };
            return Err(PointViolation {
                axis,
                what: PvtQuantity::Position,
                value: q,
                limit,
            });
        }
        let v = velocity[axis];
        if !(v.is_finite() && v.abs() <= l.velocity[axis]) {
            return Err(PointViolation {
                axis,
                what: PvtQuantity::Velocity,
                value: v,
                limit: l.velocity[axis],
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
