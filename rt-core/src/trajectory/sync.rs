//! `move_all` / `move_axis`: a phase-synchronised straight line in joint space (docs/protocol.md,
//! "move_axis, move_all"). Planning (once per command, O(1) per axis) and sampling (O(1)) may
//! run **inside the cycle**: no allocation, no panics.
//!
//! All axes follow q_i(t) = q_i0 + Δ_i·s(t) with one normalised profile s: 0 → 1, so they start
//! together, stay on the straight line and arrive together. Per axis the limits are scaled by
//! the velocity factor f: V_i = f·v_max,i, **A_i = f·a_max,i, J_i = f·j_max,i**
//! ([`AxisLimits::scaled`]).
//! The path limits are S_v = min V_i/|Δ_i|, S_a = min A_i/|Δ_i|, S_j = min J_i/|Δ_i| over the
//! moving axes (axes without a jerk limit do not constrain S_j; without any, s is a trapezoid).
//! The axis limiting each quantity gets its full limit; every other axis stays below its own.
//!
//! Reply fields of `move_all`: [`MovePlan::velocities`] (peak |q̇_i|), [`MovePlan::longest_axis`]
//! (argmax of each axis's own minimum time under its own scaled limits) and
//! [`MovePlan::duration`] = max_time_to_target (the synchronised duration, which is ≥ every
//! axis's own time and equal to the longest one when the axes' limits are proportional).
//!
//! The move starts from rest; position limits are checked by the caller (the path is monotone
//! per axis, so checking start and target suffices).
//!
//! ```
//! use mcm_rt_core::trajectory::{AxisLimits, MovePlan};
//! let deg = std::f64::consts::PI / 180.0;
//! let lim = AxisLimits { velocity: 90.0 * deg, acceleration: 180.0 * deg, jerk: None };
//! let plan = MovePlan::plan_axis([0.0; 6], 2, 90.0 * deg, &[lim; 6], 1.0).unwrap();
//! assert!((plan.duration() - 1.5).abs() < 1e-12);
//! assert_eq!(plan.longest_axis(), 2);
//! ```

use super::{AxisLimits, JointSample, PlanError, Profile1D};
use mcm_shared::NUM_AXES;

/// Largest accepted axis limit (velocity, acceleration or jerk, SI units), as in Ruckig; keeps
/// the normalised path limits far from floating-point overflow.
pub const MAX_LIMIT: f64 = 1e9;

/// Moves smaller than this (rad) are timed as if they were this long. They still follow the
/// line exactly; this only keeps the normalised limits V_i/|Δ_i| finite.
pub const MIN_MOVE: f64 = 1e-12;

/// One straight-line joint move of all six axes from rest to rest. `Copy`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MovePlan {
    start: [f64; NUM_AXES],
    target: [f64; NUM_AXES],
    delta: [f64; NUM_AXES],
    /// Normalised path s: 0 → 1.
    path: Profile1D,
    /// Each axis's own minimum time under its own scaled limits (0 if it does not move).
    axis_durations: [f64; NUM_AXES],
    longest: usize,
}

impl MovePlan {
    /// Plans the move from `start` to `target` (rad) with the velocity factor `f` in (0, 1]
    /// applied to each axis's velocity, acceleration and jerk limits.
    pub fn plan(
        start: [f64; NUM_AXES],
        target: [f64; NUM_AXES],
        limits: &[AxisLimits; NUM_AXES],
        velocity_factor: f64,
    ) -> Result<MovePlan, PlanError> {
        let f = velocity_factor;
        if !(f > 0.0 && f <= 1.0) {
            return Err(PlanError::VelocityFactor { value: f });
        }
        let mut delta = [0.0; NUM_AXES];
        for axis in 0..NUM_AXES {
            validate_axis_limits(axis, &limits[axis])?;
            let (a, b) = (start[axis], target[axis]);
            if !a.is_finite() {
                return Err(PlanError::Start { axis, value: a });
            }
            if !b.is_finite() {
                return Err(PlanError::Target { axis, value: b });
            }
            delta[axis] = b - a;
            if !delta[axis].is_finite() {
                return Err(PlanError::Delta {
                    axis,
                    value: delta[axis],
                });
            }
        }
        let (mut s_v, mut s_a, mut s_j) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let mut axis_durations = [0.0; NUM_AXES];
        let mut moving = false;
        for axis in 0..NUM_AXES {
            if delta[axis] == 0.0 {
                continue;
            }
            moving = true;
            let l = limits[axis].scaled(f);
            let d = delta[axis].abs().max(MIN_MOVE);
            s_v = s_v.min(l.velocity / d);
            s_a = s_a.min(l.acceleration / d);
            if let Some(j) = l.jerk {
                s_j = s_j.min(j / d);
            }
            axis_durations[axis] = Profile1D::plan(delta[axis], l)?.duration();
        }
        let path = if moving {
            let jerk = if s_j.is_finite() { Some(s_j) } else { None };
            Profile1D::plan(
                1.0,
                AxisLimits {
                    velocity: s_v,
                    acceleration: s_a,
                    jerk,
                },
            )?
        } else {
            Profile1D::default()
        };
        let mut longest = 0;
        for axis in 1..NUM_AXES {
            if axis_durations[axis] > axis_durations[longest] {
                longest = axis;
            }
        }
        Ok(MovePlan {
            start,
            target,
            delta,
            path,
            axis_durations,
            longest,
        })
    }

    /// `move_axis`: the same move with only `axis` (0-based) going to `target_position`.
    pub fn plan_axis(
        start: [f64; NUM_AXES],
        axis: usize,
        target_position: f64,
        limits: &[AxisLimits; NUM_AXES],
        velocity_factor: f64,
    ) -> Result<MovePlan, PlanError> {
        let mut target = start;
        match target.get_mut(axis) {
            Some(q) => *q = target_position,
            None => return Err(PlanError::AxisIndex { axis }),
        }
        MovePlan::plan(start, target, limits, velocity_factor)
    }

    /// Synchronised duration (s): `max_time_to_target` of the `move_all` result.
    pub fn duration(&self) -> f64 {
        self.path.duration()
    }

    /// Commanded state at `t` seconds after the start; `t` is clamped to [0, duration] (NaN
    /// counts as 0). From `duration()` on: exactly the target, at rest.
    pub fn sample(&self, t: f64) -> JointSample {
        if t >= self.path.duration() {
            return JointSample {
                position: self.target,
                ..JointSample::default()
            };
        }
        let (s, ds, dds) = self.path.sample(t);
        let mut out = JointSample::default();
        for i in 0..NUM_AXES {
            out.position[i] = self.start[i] + self.delta[i] * s;
            out.velocity[i] = self.delta[i] * ds;
            out.acceleration[i] = self.delta[i] * dds;
        }
        out
    }

    /// Peak |velocity| per axis (rad/s): the "velocities used" of the `move_all` result.
    pub fn velocities(&self) -> [f64; NUM_AXES] {
        self.delta.map(|d| d.abs() * self.path.peak_velocity())
    }

    /// Peak |acceleration| per axis (rad/s²).
    pub fn accelerations(&self) -> [f64; NUM_AXES] {
        self.delta.map(|d| d.abs() * self.path.peak_acceleration())
    }

    /// 0-based index of the axis whose own minimum time is longest (first one on ties; 0 if
    /// nothing moves).
    pub fn longest_axis(&self) -> usize {
        self.longest
    }

    /// Each axis's own minimum time (s) under its own scaled limits; 0 for axes that stay.
    pub fn axis_durations(&self) -> [f64; NUM_AXES] {
        self.axis_durations
    }

    pub fn start(&self) -> [f64; NUM_AXES] {
        self.start
    }

    pub fn target(&self) -> [f64; NUM_AXES] {
        self.target
    }

    /// The normalised path profile s(t), 0 → 1.
    pub fn path(&self) -> &Profile1D {
        &self.path
    }
}

fn validate_axis_limits(axis: usize, l: &AxisLimits) -> Result<(), PlanError> {
    let bad = |x: f64| !(x.is_finite() && x > 0.0 && x <= MAX_LIMIT);
    let err = |name, value| {
        Err(PlanError::AxisLimit {
            axis,
            name,
            value,
            max: MAX_LIMIT,
        })
    };
    if bad(l.velocity) {
        return err("velocity", l.velocity);
    }
    if bad(l.acceleration) {
        return err("acceleration", l.acceleration);
    }
    match l.jerk {
        Some(j) if bad(j) => err("jerk", j),
        _ => Ok(()),
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // tests index several per-axis arrays at once
mod tests;
