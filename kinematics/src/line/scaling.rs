//! The time law's bounds: the largest ds/dt (V), d²s/dt² (A) and d³s/dt³ (J) that keep the
//! TCP within the request and every axis within its limits all along the path.
//!
//! Along the path q̇ = q′ṡ, q̈ = q″ṡ² + q′s̈ and q⃛ = q‴ṡ³ + 3q″ṡs̈ + q′s⃛ (′: d/ds). With the
//! path's bounds Q1, Q2, Q3 of |q′|, |q″|, |q‴| ([`super::check`]) and |ṡ| ≤ V, |s̈| ≤ A,
//! |s⃛| ≤ J, each axis stays within its velocity v, acceleration a and jerk j when
//!
//! - Q1·V ≤ v;
//! - Q2·V² ≤ a/2 and Q1·A ≤ a − Q2·V² (half the acceleration is kept for the path's bend);
//! - Q3·V³ ≤ j/4, 3·Q2·V·A ≤ j/4 and Q1·J ≤ j − Q3·V³ − 3·Q2·V·A.
//!
//! The TCP's speed is |p₁ − p₀|·ṡ and its acceleration |p₁ − p₀|·s̈, its angular speed and
//! acceleration the turn's angle times ṡ and s̈: V and A are also held to the request (the
//! angular ones to the request divided by [`ROTATION_RADIUS_M`]). V is chosen first, the
//! largest the velocity rows allow, then A, then J. Without any axis's jerk limit the law is
//! a trapezoid.

use super::check::Bounds;
use super::profile::PathProfile;
use super::{JointLimits, ROTATION_RADIUS_M};
use crate::N;
use nalgebra::Vector6;

/// The time law of a path with derivative `twist` (per unit s), for the requested TCP
/// `velocity` [m/s] and `acceleration` [m/s²].
pub(super) fn profile(
    bounds: &Bounds,
    limits: &JointLimits,
    velocity: f64,
    acceleration: f64,
    twist: &Vector6<f64>,
) -> PathProfile {
    let length = twist.fixed_rows::<3>(0).norm();
    let angle = twist.fixed_rows::<3>(3).norm();
    let (mut v, mut a) = (f64::INFINITY, f64::INFINITY);
    if length > 0.0 {
        v = v.min(velocity / length);
        a = a.min(acceleration / length);
    }
    if angle > 0.0 {
        v = v.min(velocity / ROTATION_RADIUS_M / angle);
        a = a.min(acceleration / ROTATION_RADIUS_M / angle);
    }
    if !(v.is_finite() && a.is_finite()) {
        // No displacement and no turn: nothing to move.
        return PathProfile::default();
    }
    let Bounds {
        rate: q1,
        curvature: q2,
        third: q3,
    } = *bounds;
    for i in 0..N {
        if q1[i] > 0.0 {
            v = v.min(limits.velocity[i] / q1[i]);
        }
        if q2[i] > 0.0 {
            v = v.min((limits.acceleration[i] / (2.0 * q2[i])).sqrt());
        }
        if let Some(j) = limits.jerk[i]
            && q3[i] > 0.0
        {
            v = v.min((j / (4.0 * q3[i])).cbrt());
        }
    }
    for i in 0..N {
        if q1[i] > 0.0 {
            a = a.min((limits.acceleration[i] - q2[i] * v * v) / q1[i]);
        }
        if let Some(j) = limits.jerk[i]
            && q2[i] > 0.0
        {
            a = a.min(j / (12.0 * q2[i] * v));
        }
    }
    let mut jerk = f64::INFINITY;
    for i in 0..N {
        if let Some(j) = limits.jerk[i]
            && q1[i] > 0.0
        {
            jerk = jerk.min((j - q3[i] * v * v * v - 3.0 * q2[i] * v * a) / q1[i]);
        }
    }
    PathProfile::new(v, a, jerk.is_finite().then_some(jerk))
}
