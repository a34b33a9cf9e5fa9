//! The check of the whole path before anything moves, and the joint-space bounds the time law
//! needs.
//!
//! The path is sampled at n + 1 points (n intervals of equal s, n a multiple of [`KNOTS`]: at
//! most [`STEP_M`] of TCP travel and [`STEP_DEG`] of turn apart, n ≤ [`MAX_INTERVALS`]). At
//! each point: the inverse kinematics of the start's branch, continued from the previous
//! point (each angle the whole-turn shift nearest it); each axis within its reachable range;
//! the joint rates dq/ds = J⁻¹ξ.
//!
//! **Between two points** the path is checked from the values and rates at both ends:
//! - an axis's rate over the interval is taken as at most Lᵢ = max(|q′ᵢ(a)|, |q′ᵢ(b)|) +
//!   |q′ᵢ(b) − q′ᵢ(a)| (the larger end rate plus the change across the interval). A step
//!   |Δqᵢ| above 2·Lᵢ·h (h the interval in s) is a **jump**: the branch is discontinuous
//!   there, which happens only where the path crosses a singularity between the points;
//! - where an axis's rate changes sign it turns within the interval, and may overshoot both
//!   ends by up to Lᵢ·h/2 (the bound of a function with rate at most Lᵢ): that bound must
//!   lie within the reachable range;
//! - a singularity measure whose rate is at most M over the interval is at least the mean of
//!   the ends less M·h/2 (never more than the smaller end), and must be at least its margin
//!   ([`SingularityMargins::DEFAULT`]). The wrist measure (the angle between axes 4 and 6, a function of θ5) changes
//!   at most as fast as axis 5 (L₅); the shoulder measure (the wrist centre's distance from
//!   axis 1) and the elbow's reach (the wrist centre's distance from axis 2, which sets the
//!   elbow angle) at most as fast as the wrist centre moves, |Δp| + |Δθ|·r for a turn Δθ and
//!   the wrist centre r from the TCP. So the elbow, whose measure changes fastest near the
//!   stretched arm (5° there is 0.6 mm of reach on the P-Rob2), is checked in reach, not in
//!   angle.
//!
//! The time law's bounds, per interval: the largest |dq/ds| at its ends, |d²q/ds²| (the
//! differences of the rates over it and the interval before) and |d³q/ds³| (the difference of
//! those), each raised by what the next derivative allows over half an interval (the third
//! derivative by 25 %); [`Pace`] takes them in order along the path.

use super::profile::PathProfile;
use super::scaling::Pace;
use super::{
    KNOTS, LineError, LinePlan, MAX_INTERVALS, PathPoint, STEP_DEG, STEP_M, Singularity,
    joint_rates,
};
use crate::limits::LIMIT_TOLERANCE_RAD;
use crate::{Kinematics, N, Singularities, SingularityMargins};
use nalgebra::{Point3, Vector6};
use std::f64::consts::FRAC_PI_2;

/// The largest |dq/ds|, |d²q/ds²|, |d³q/ds³| of each axis over an interval of the path.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Bounds {
    pub rate: [f64; N],
    pub curvature: [f64; N],
    pub third: [f64; N],
}

/// One checked point of the path.
#[derive(Clone, Copy)]
pub(super) struct Point {
    at: PathPoint,
    q: [f64; N],
    rate: Vector6<f64>,
    measures: Singularities,
    /// The wrist centre's distance from axis 2 in the arm's plane [m].
    reach: f64,
}

impl Kinematics {
    /// The wrist centre's distance from the TCP [m].
    fn wrist_centre_from_tcp(&self) -> f64 {
        let centre = Point3::from(-self.shape.wrist_offset);
        (self.tcp_inverse * centre).coords.norm()
    }

    /// The reach the elbow angle θ3 + forearm angle gives (the wrist centre's distance from
    /// axis 2), and the reach window inside the elbow margin.
    fn elbow_reach(&self, q: &[f64; N], margin: f64) -> (f64, (f64, f64)) {
        let (a2, l) = (self.shape.a2, self.shape.forearm);
        let phi = q[2] + self.links[2].offset + self.shape.forearm_angle;
        let sq = a2 * a2 + l * l;
        let reach = (sq + 2.0 * a2 * l * phi.cos()).max(0.0).sqrt();
        let w = 2.0 * (a2 * l).abs() * margin.cos();
        (reach, ((sq - w).max(0.0).sqrt(), (sq + w).sqrt()))
    }

    /// The elbow measure (as [`Singularities::elbow_rad`]) at a reach [rad].
    fn elbow_measure(&self, reach: f64) -> f64 {
        let (a2, l) = (self.shape.a2, self.shape.forearm);
        let c = (reach * reach - a2 * a2 - l * l).abs() / (2.0 * (a2 * l).abs());
        c.min(1.0).acos()
    }
}

/// Walk the path of `plan` from `start`: check it, store the knots and the joint target, and
/// return the time law of the pace `pace_for(h)` gives for intervals h long (the zero law
/// when it gives none) with the bounds of the joint derivatives over each interval.
pub(super) fn walk(
    plan: &mut LinePlan,
    start: &[f64; N],
    pace_for: impl FnOnce(f64) -> Option<Pace>,
) -> Result<PathProfile, LineError> {
    let kin = plan.kin;
    let margins = SingularityMargins::DEFAULT;
    let length = plan.twist.fixed_rows::<3>(0).norm();
    let angle = plan.turn.norm();
    let wanted = (length / STEP_M).max(angle / STEP_DEG.to_radians()).ceil();
    let per_knot = ((wanted / KNOTS as f64).ceil() as usize).clamp(1, MAX_INTERVALS / KNOTS);
    let n = per_knot * KNOTS;
    let h = 1.0 / n as f64;
    let centre_step = h * (length + angle * kin.wrist_centre_from_tcp());
    let mut pace = pace_for(h);
    let mut prev: Option<Point> = None;
    let mut prev_change: Vector6<f64> = Vector6::zeros();
    for k in 0..=n {
        let s = k as f64 * h;
        let pose = plan.pose_at(s);
        let at = PathPoint {
            fraction: s,
            position: pose.translation.vector.into(),
        };
        let q = match &prev {
            None => *start,
            Some(p) => kin
                .inverse_branch(&pose, plan.branch, &p.q)
                .map_err(|cause| LineError::Unreachable { at, cause })?,
        };
        for (i, (v, r)) in q.iter().zip(kin.ranges()).enumerate() {
            if *v < r.min - LIMIT_TOLERANCE_RAD || *v > r.max + LIMIT_TOLERANCE_RAD {
                return Err(out_of_range(&kin, at, i, *v));
            }
        }
        let measures = kin.singularities(&q);
        let (reach, window) = kin.elbow_reach(&q, margins.elbow_rad);
        let Some(rate) = joint_rates(&kin.tcp_jacobian(&q), &plan.twist) else {
            return Err(nearest(at, &measures, &margins));
        };
        let here = Point {
            at,
            q,
            rate,
            measures,
            reach,
        };
        if let Some(p) = &prev {
            between(&kin, p, &here, h, centre_step, window, &margins)?;
            let change = (rate - p.rate) / h;
            let mut bounds = Bounds::default();
            for i in 0..N {
                let (third, before) = match k {
                    1 => (0.0, 0.0),
                    _ => ((change[i] - prev_change[i]).abs() / h, prev_change[i].abs()),
                };
                bounds.third[i] = 1.25 * third;
                bounds.curvature[i] = change[i].abs().max(before) + third * h / 2.0;
                bounds.rate[i] = rate[i].abs().max(p.rate[i].abs()) + bounds.curvature[i] * h / 2.0;
            }
            if let Some(pace) = &mut pace {
                pace.push(&bounds);
            }
            prev_change = change;
        }
        if k % per_knot == 0 {
            plan.knots[k / per_knot] = q;
        }
        let knot = &plan.knots[k / per_knot];
        if let Some(i) = (0..N).find(|&i| (q[i] - knot[i]).abs() >= FRAC_PI_2) {
            return Err(LineError::JointJump {
                at,
                axis: i + 1,
                step_deg: (q[i] - knot[i]).to_degrees(),
                within: h * per_knot as f64,
                allowed_deg: 90.0,
            });
        }
        prev = Some(here);
    }
    if let Some(p) = prev {
        plan.joint_target = p.q;
    }
    Ok(pace.map(Pace::profile).unwrap_or_default())
}

/// The checks between two neighbouring points `a` and `b` (the module's doc).
fn between(
    kin: &Kinematics,
    a: &Point,
    b: &Point,
    h: f64,
    centre_step: f64,
    (reach_min, reach_max): (f64, f64),
    margins: &SingularityMargins,
) -> Result<(), LineError> {
    let lipschitz = |i: usize| a.rate[i].abs().max(b.rate[i].abs()) + (b.rate[i] - a.rate[i]).abs();
    for i in 0..N {
        let (l, step) = (lipschitz(i) * h, b.q[i] - a.q[i]);
        if step.abs() > 2.0 * l + 1e-9 {
            return Err(LineError::JointJump {
                at: b.at,
                axis: i + 1,
                step_deg: step.to_degrees(),
                within: h,
                allowed_deg: (2.0 * l).to_degrees(),
            });
        }
        let (mid, r) = ((a.q[i] + b.q[i]) / 2.0, kin.ranges()[i]);
        let turning_up = a.rate[i] > 0.0 && b.rate[i] < 0.0;
        let turning_down = a.rate[i] < 0.0 && b.rate[i] > 0.0;
        let higher = if b.q[i] > a.q[i] {
            (b.at, a.at)
        } else {
            (a.at, b.at)
        };
        if turning_up && mid + l / 2.0 > r.max + LIMIT_TOLERANCE_RAD {
            return Err(out_of_range(kin, higher.0, i, mid + l / 2.0));
        }
        if turning_down && mid - l / 2.0 < r.min - LIMIT_TOLERANCE_RAD {
            return Err(out_of_range(kin, higher.1, i, mid - l / 2.0));
        }
    }
    let lower = |ma: f64, mb: f64, step: f64| (ma + mb) / 2.0 - step / 2.0;
    let worse = |ma: f64, mb: f64| if ma <= mb { a.at } else { b.at };
    let (ma, mb) = (&a.measures, &b.measures);
    let wrist = lower(ma.wrist_rad, mb.wrist_rad, lipschitz(4) * h);
    if wrist < margins.wrist_rad {
        let at = worse(ma.wrist_rad, mb.wrist_rad);
        return Err(singular(at, Singularity::Wrist, wrist, margins.wrist_rad));
    }
    let shoulder = lower(ma.shoulder_m, mb.shoulder_m, centre_step);
    if shoulder < margins.shoulder_m {
        let at = worse(ma.shoulder_m, mb.shoulder_m);
        return Err(singular(
            at,
            Singularity::Shoulder,
            shoulder,
            margins.shoulder_m,
        ));
    }
    let mid = (a.reach + b.reach) / 2.0;
    let (low, high) = (mid - centre_step / 2.0, mid + centre_step / 2.0);
    if low < reach_min || high > reach_max {
        let elbow = kin.elbow_measure(low).min(kin.elbow_measure(high));
        let at = worse(ma.elbow_rad, mb.elbow_rad);
        return Err(singular(at, Singularity::Elbow, elbow, margins.elbow_rad));
    }
    Ok(())
}

fn out_of_range(kin: &Kinematics, at: PathPoint, i: usize, value: f64) -> LineError {
    let r = kin.ranges()[i];
    LineError::OutOfRange {
        at,
        axis: i + 1,
        value_deg: value.to_degrees(),
        min_deg: r.min.to_degrees(),
        max_deg: r.max.to_degrees(),
    }
}

const SINGULARITIES: [Singularity; 3] = [
    Singularity::Wrist,
    Singularity::Elbow,
    Singularity::Shoulder,
];

/// A singularity's measure and margin [rad or m].
fn measure(which: Singularity, m: &Singularities, margins: &SingularityMargins) -> (f64, f64) {
    match which {
        Singularity::Wrist => (m.wrist_rad, margins.wrist_rad),
        Singularity::Elbow => (m.elbow_rad, margins.elbow_rad),
        Singularity::Shoulder => (m.shoulder_m, margins.shoulder_m),
    }
}

/// The error for a measure `value` against its `margin` [rad or m]; angles said in degrees.
fn singular(at: PathPoint, singularity: Singularity, value: f64, margin: f64) -> LineError {
    let unit = |v: f64| match singularity {
        Singularity::Shoulder => v,
        Singularity::Wrist | Singularity::Elbow => v.to_degrees(),
    };
    LineError::Singular {
        at,
        singularity,
        value: unit(value.max(0.0)),
        margin: unit(margin),
    }
}

/// The singularity nearest in proportion to its margin (where the Jacobian cannot be
/// inverted although every measure is outside its margin: only by rounding).
fn nearest(at: PathPoint, m: &Singularities, margins: &SingularityMargins) -> LineError {
    let ratio = |w: Singularity| {
        let (value, margin) = measure(w, m, margins);
        value / margin
    };
    let mut which = Singularity::Wrist;
    for w in SINGULARITIES {
        if ratio(w) < ratio(which) {
            which = w;
        }
    }
    let (value, margin) = measure(which, m, margins);
    singular(at, which, value, margin)
}

/// Points and the checks between them, for the tests of what lies between two points.
#[cfg(test)]
pub(super) mod between_for_test {
    pub(in crate::line) use super::Point;
    use super::*;

    /// The point of configuration `q` with the joint rates `rates` (per unit s).
    pub(in crate::line) fn point(kin: &Kinematics, q: &[f64; N], rates: [f64; N]) -> Point {
        Point {
            at: PathPoint {
                fraction: 0.0,
                position: kin.tcp_pose(q).translation.vector.into(),
            },
            q: *q,
            rate: Vector6::from(rates),
            measures: kin.singularities(q),
            reach: kin.elbow_reach(q, 0.0).0,
        }
    }

    /// The checks between `a` and `b`, `h` apart in s, the wrist centre moving `centre_step`.
    pub(in crate::line) fn check(
        kin: &Kinematics,
        a: &Point,
        b: &Point,
        h: f64,
        centre_step: f64,
    ) -> Result<(), LineError> {
        let margins = SingularityMargins::DEFAULT;
        let window = kin.elbow_reach(&a.q, margins.elbow_rad).1;
        between(kin, a, b, h, centre_step, window, &margins)
    }
}
