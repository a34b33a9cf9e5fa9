//! The plan's PVT points checked as the core checks a `pvt_points` batch (docs/protocol.md,
//! "pvt_points"), so that the node never feeds the core a batch it refuses halfway through a
//! motion: each point's position in the reachable range and speed within the limit, exactly;
//! and the cubic Hermite segment the core interpolates from the previous point (from the start
//! state for the first) over `dt`: positions at both ends and at its turning points, speeds at
//! both ends and at their extremum, accelerations at both ends (where a cubic's are largest).
//! The segments are not the plan: where the plan's acceleration steps between two PVT points
//! the core's cubic through them accelerates harder, and this is where that shows.
//!
//! The core accepts a segment's values up to a relative 1e-9 above the limits; this check
//! allows half of that, so that round-off in the degree conversion cannot tip a point over.

use super::error::GoalError;
use super::joints::{AxisLimits, Joints};
use super::plan::Plan;
use super::polynomial::{Knot, Polynomial};
use super::quantity::Quantity;
use super::{StartState, within};
use mcm_shared::NUM_AXES;

/// The share of the core's tolerance this check allows (see the module doc).
const MARGIN: f64 = 0.5e-9;

/// Check every PVT point of `plan` and the core's segment to it (see the module doc).
pub fn check(plan: &Plan, start: &StartState, joints: &Joints) -> Result<(), GoalError> {
    let dt = plan.dt();
    let mut prev = (start.position, start.velocity);
    for k in 0..plan.point_count() {
        let pt = plan.pvt_point(k);
        // In radians as the core reads them.
        let p: [f64; NUM_AXES] = pt.position_deg.map(f64::to_radians);
        let v: [f64; NUM_AXES] = pt.velocity_deg_s.map(f64::to_radians);
        let t_end = plan.time_from_start((k + 1) as f64 * dt);
        let fail = |axis: usize, quantity: Quantity, value: f64, tau: f64| {
            let l = &joints.limits()[axis];
            let joint = joints.name(axis).to_string();
            let time = t_end - dt + tau;
            let pvt = Some(k);
            match quantity {
                Quantity::Position => GoalError::PositionLimit {
                    joint,
                    time,
                    value,
                    min: l.min,
                    max: l.max,
                    pvt,
                },
                _ => GoalError::Limit {
                    joint,
                    quantity,
                    time,
                    value,
                    limit: if quantity == Quantity::Velocity {
                        l.velocity
                    } else {
                        l.acceleration
                    },
                    pvt,
                },
            }
        };
        for (axis, l) in joints.limits().iter().enumerate() {
            if !(p[axis] >= l.min && p[axis] <= l.max) {
                return Err(fail(axis, Quantity::Position, p[axis], dt));
            }
            if !within(v[axis], l.velocity) {
                return Err(fail(axis, Quantity::Velocity, v[axis], dt));
            }
            let k0 = Knot {
                p: prev.0[axis],
                v: prev.1[axis],
                a: None,
            };
            let k1 = Knot {
                p: p[axis],
                v: v[axis],
                a: None,
            };
            if let Err((quantity, value, tau)) = segment(k0, k1, dt, l) {
                return Err(fail(axis, quantity, value, tau));
            }
        }
        prev = (p, v);
    }
    Ok(())
}

/// The core's cubic from `k0` to `k1` over `dt` against the limits `l`: the failing quantity,
/// its value and where (τ) on the segment.
fn segment(k0: Knot, k1: Knot, dt: f64, l: &AxisLimits) -> Result<(), (Quantity, f64, f64)> {
    let cubic = Polynomial::hermite(k0, k1, dt);
    // p'(τ) = k0.v + 2·c2·τ + 3·c3·τ², from the values at τ = 0 and dt.
    let (_, _, a0) = cubic.eval(0.0);
    let (_, _, a1) = cubic.eval(dt);
    let (c2, c3) = (a0 / 2.0, (a1 - a0) / (6.0 * dt));
    let inside = |tau: &f64| *tau > 0.0 && *tau < dt;
    // Position and velocity at τ, the points' own values at the ends.
    let at = |tau: f64| {
        if tau == 0.0 {
            (k0.p, k0.v)
        } else if tau == dt {
            (k1.p, k1.v)
        } else {
            let (p, v, _) = cubic.eval(tau);
            (p, v)
        }
    };
    // Turning points of the position: roots of p'.
    let turning = roots(3.0 * c3, 2.0 * c2, k0.v);
    let positions = [Some(0.0), Some(dt)]
        .into_iter()
        .chain(turning.into_iter().map(|r| r.filter(inside)));
    for tau in positions.flatten() {
        let p = at(tau).0;
        if !(p >= l.min - MARGIN && p <= l.max + MARGIN) {
            return Err((Quantity::Position, p, tau));
        }
    }
    // Speeds: both ends and the extremum of p' (where p'' = 0).
    let extremum = (c3 != 0.0).then(|| -c2 / (3.0 * c3)).filter(inside);
    for tau in [Some(0.0), Some(dt), extremum].into_iter().flatten() {
        let v = at(tau).1;
        if !within(v, l.velocity * (1.0 + MARGIN)) {
            return Err((Quantity::Velocity, v, tau));
        }
    }
    for (tau, a) in [(0.0, a0), (dt, a1)] {
        if !within(a, l.acceleration * (1.0 + MARGIN)) {
            return Err((Quantity::Acceleration, a, tau));
        }
    }
    Ok(())
}

/// The real roots of a·x² + b·x + c (none, one or two).
fn roots(a: f64, b: f64, c: f64) -> [Option<f64>; 2] {
    if a == 0.0 {
        return [(b != 0.0).then(|| -c / b), None];
    }
    let disc = b * b - 4.0 * a * c;
    if disc.is_nan() || disc < 0.0 {
        return [None, None];
    }
    let s = disc.sqrt();
    // Avoid cancellation: the root of larger magnitude first, the other from the product.
    let q = -0.5 * (b + s.copysign(b));
    if q == 0.0 {
        return [Some(0.0), None];
    }
    [Some(q / a), Some(c / q)]
}

#[cfg(test)]
mod tests;
