//! Online re-planning: a move of one axis from whatever state it is in (position, velocity,
//! acceleration) to a target, at rest, within the axis's limits; and [`JointPlan`], six such
//! plans that run independently (each with its own clock). Pure functions, O(1) per axis
//! (a bounded bisection), allocation- and panic-free: they run **inside the cycle**.
//!
//! [`plan_from_state`] chains three stages (limits: `full` = the axis's maximum, `scaled` =
//! those times the velocity factor f, as for rest-to-rest moves):
//! 1. **settle** (full limits): bring the acceleration to 0 and the velocity into
//!    [−f·v_max, f·v_max] — with a jerk limit the acceleration ramps down at the full jerk
//!    (Ruckig's brake, [`super::controlled_stop`], in a frame moving at the settled velocity),
//!    without one it is dropped at once (a trapezoid may switch its acceleration);
//! 2. **approach**: if the axis already moves toward the target and can stop in time, ramp to
//!    a peak velocity, cruise, and ramp to rest exactly on the target (the peak is the highest
//!    that fits, found by bisection on a monotone distance); the ramps use the scaled limits,
//!    or the full acceleration and jerk when only those stop the axis in time;
//! 3. otherwise **turn back**: brake to rest at the full limits, then the standard rest-to-rest
//!    profile ([`super::Profile1D`]) to the target at the scaled limits.
//!
//! Velocity and acceleration stay within the full limits throughout, and after the settle
//! stage within the scaled ones (except the braking of stage 2/3 at full deceleration); the
//! state is continuous at the switch (the plan starts at the given state). The plan is not
//! time-optimal in general (the settle stage always passes through a = 0), but it is
//! continuous, bounded and exact at the end. The caller checks the position range
//! ([`AxisPlan::position_range`]): a plan that turns back overshoots where the axis was going.
//!
//! ```
//! use mcm_rt_core::trajectory::{AxisLimits, online::plan_from_state};
//! let lim = AxisLimits { velocity: 1.5, acceleration: 3.0, jerk: Some(30.0) };
//! // Moving at 1 rad/s and still accelerating; re-targeted behind the axis.
//! let plan = plan_from_state(0, 0.5, 1.0, 2.0, -0.2, lim, 0.5).unwrap();
//! assert_eq!(plan.sample(0.0), (0.5, 1.0, 2.0));
//! assert_eq!(plan.sample(plan.duration()), (-0.2, 0.0, 0.0));
//! assert!(plan.position_range().1 > 0.5); // it overshoots before it turns back
//! ```

use super::controlled_stop::brake_phases;
use super::segments::{AxisPlan, Builder, ramp_distance};
use super::{AxisLimits, JointSample, MovePlan, PlanError, Profile1D};
use mcm_shared::NUM_AXES;

/// Plans axis `axis` (0-based, for errors) from (p0, v0, a0) to rest at `target`, with the
/// velocity factor `f` in (0, 1] applied to `limits` for the approach. See the module doc.
pub fn plan_from_state(
    axis: usize,
    p0: f64,
    v0: f64,
    a0: f64,
    target: f64,
    limits: AxisLimits,
    f: f64,
) -> Result<AxisPlan, PlanError> {
    if !(f > 0.0 && f <= 1.0) {
        return Err(PlanError::VelocityFactor { value: f });
    }
    limits.validate()?;
    for value in [p0, v0, a0] {
        if !value.is_finite() {
            return Err(PlanError::Start { axis, value });
        }
    }
    if !target.is_finite() {
        return Err(PlanError::Target {
            axis,
            value: target,
        });
    }
    let scaled = limits.scaled(f);
    let mut b = Builder::new(p0, v0, a0);

    // 1. Settle: a = 0, |v| within the scaled limit.
    let natural = match limits.jerk {
        Some(j) => v0 + a0 * a0.abs() / (2.0 * j),
        None => v0,
    };
    let v1 = natural.clamp(-scaled.velocity, scaled.velocity);
    if a0 != 0.0 || v1 != v0 {
        let phases = brake_phases(v0 - v1, a0, limits.acceleration, limits.jerk)
            .map_err(|_| PlanError::Start { axis, value: v0 })?;
        for (duration, a, j) in phases {
            b.set_acceleration(a);
            b.push(duration, j);
        }
        b.set_acceleration(0.0);
        b.set_velocity(v1);
    }

    // 2. or 3.
    let d = target - b.state().0;
    let sign = if d != 0.0 { d.signum() } else { -v1.signum() };
    let (u, dist) = (sign * v1, d.abs());
    let braking = AxisLimits {
        velocity: scaled.velocity,
        ..limits
    };
    let fits = |l: &AxisLimits| u > 0.0 && ramp_distance(u, 0.0, l) <= dist;
    if v1 == 0.0 {
        rest_to_rest(&mut b, d, &scaled)?;
    } else if fits(&scaled) {
        approach(&mut b, sign, u, dist, &scaled);
    } else if fits(&braking) {
        approach(&mut b, sign, u, dist, &braking);
    } else {
        b.ramp(0.0, &limits);
        let back = target - b.state().0;
        rest_to_rest(&mut b, back, &scaled)?;
    }
    b.finish(target)
}

/// From speed `u` > 0 toward a target `dist` away (direction `sign`): ramp to the highest peak
/// that still stops on the target, cruise the rest, ramp to rest.
fn approach(b: &mut Builder, sign: f64, u: f64, dist: f64, lim: &AxisLimits) {
    let total = |vp: f64| ramp_distance(u, vp, lim) + ramp_distance(vp, 0.0, lim);
    let vp = if total(lim.velocity) <= dist {
        lim.velocity
    } else {
        // total(u) <= dist < total(v_max), increasing in vp.
        let (mut lo, mut hi) = (u, lim.velocity);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if total(mid) <= dist {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    };
    let cruise = ((dist - total(vp)) / vp).max(0.0);
    b.ramp(sign * vp, lim);
    b.cruise(cruise);
    b.ramp(0.0, lim);
}

/// The standard rest-to-rest profile over `d`, appended from rest.
fn rest_to_rest(b: &mut Builder, d: f64, lim: &AxisLimits) -> Result<(), PlanError> {
    let profile = Profile1D::plan(d, *lim)?;
    if profile.duration() == 0.0 {
        return Ok(());
    }
    let pt = profile.phase_times();
    b.ramp(d.signum() * profile.peak_velocity(), lim);
    b.cruise(pt[4] - pt[3]);
    b.ramp(0.0, lim);
    Ok(())
}

/// Six axis plans, each with its own clock: a `move_axis` replaces one, a `move_all` all six.
/// `Copy`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointPlan {
    axes: [AxisPlan; NUM_AXES],
    /// Time since each axis's plan started (s).
    t: [f64; NUM_AXES],
}

impl JointPlan {
    /// Every axis holds its position.
    pub fn hold(position: [f64; NUM_AXES]) -> JointPlan {
        JointPlan {
            axes: position.map(AxisPlan::hold),
            t: [0.0; NUM_AXES],
        }
    }

    /// Six plans starting now.
    pub fn new(axes: [AxisPlan; NUM_AXES]) -> JointPlan {
        JointPlan {
            axes,
            t: [0.0; NUM_AXES],
        }
    }

    /// The phase-synchronised straight line of a [`MovePlan`], as six axis plans (the same
    /// phases on every axis, scaled by its share of the path).
    pub fn from_move(plan: &MovePlan) -> Result<JointPlan, PlanError> {
        let path = plan.path();
        let (start, target) = (plan.start(), plan.target());
        let pt = path.phase_times();
        let mut axes = start.map(AxisPlan::hold);
        for (i, axis) in axes.iter_mut().enumerate() {
            let delta = target[i] - start[i];
            if delta == 0.0 || path.duration() == 0.0 {
                *axis = AxisPlan::hold(target[i]);
                continue;
            }
            let scale = delta.abs();
            let lim = AxisLimits {
                velocity: scale * path.peak_velocity(),
                acceleration: scale * path.peak_acceleration(),
                jerk: path.jerk().map(|j| scale * j),
            };
            let mut b = Builder::new(start[i], 0.0, 0.0);
            b.ramp(delta * path.peak_velocity(), &lim);
            b.cruise(pt[4] - pt[3]);
            b.ramp(0.0, &lim);
            *axis = b.finish(target[i])?;
        }
        Ok(JointPlan::new(axes))
    }

    /// Replace the plan of `axis` (0-based; ignored if out of range), starting now; the other
    /// axes carry on.
    pub fn set_axis(&mut self, axis: usize, plan: AxisPlan) {
        if let (Some(a), Some(t)) = (self.axes.get_mut(axis), self.t.get_mut(axis)) {
            *a = plan;
            *t = 0.0;
        }
    }

    /// The plan of axis `i` (0-based).
    pub fn axis(&self, i: usize) -> &AxisPlan {
        &self.axes[i.min(NUM_AXES - 1)]
    }

    /// Advance every axis's clock by `dt` and return the commanded state then.
    pub fn advance(&mut self, dt: f64) -> JointSample {
        for (t, a) in self.t.iter_mut().zip(&self.axes) {
            // Past the end (bounded): the plan's exact end state.
            *t = (*t + dt).min(a.duration() + 1.0);
        }
        self.sample()
    }

    /// The commanded state now.
    pub fn sample(&self) -> JointSample {
        let mut out = JointSample::default();
        for i in 0..NUM_AXES {
            (out.position[i], out.velocity[i], out.acceleration[i]) =
                self.axes[i].sample(self.t[i]);
        }
        out
    }

    /// Seconds until the last axis arrives (0 when every axis is at its target).
    pub fn remaining(&self) -> f64 {
        (0..NUM_AXES).fold(0.0, |r: f64, i| {
            r.max((self.axes[i].duration() - self.t[i]).max(0.0))
        })
    }

    /// Every axis arrived.
    pub fn finished(&self) -> bool {
        (0..NUM_AXES).all(|i| self.t[i] >= self.axes[i].duration() && self.t[i] > 0.0)
    }
}

#[cfg(test)]
mod tests;
