//! The joint velocity target of a TCP velocity (`set_cartesian_velocity`): each cycle, at the
//! commanded configuration, the requested twist (in the tool frame turned into the base frame
//! by the TCP's present orientation) through the TCP's geometric Jacobian, then scaled as a
//! whole into what every axis's ramp allows. The ramp of VELOCITY_CONTROL ([`super::ramp`])
//! then takes it as its target, as it takes `set_velocities`'.
//!
//! Runs inside the cycle (pure, fixed-size `nalgebra`, allocation-free, panic-free).
//!
//! **Away from singularities** (every measure of `mcm_kinematics::Singularities` at least its
//! margin, [`SingularityMargins::DEFAULT`]) the joint velocities are the exact solution
//! `J q̇ = ξ`. **Inside a margin** they are the damped least-squares solution
//! `q̇ = Jᵀ (J Jᵀ + λ² I)⁻¹ ξ`, with `λ² = λ_max² (1 − r)²` where `r` is the smallest ratio of a
//! measure to its margin: 0 at the margin, [`DAMPING_MAX`]² at the singularity. The component
//! of the motion towards the singularity then slows down (in proportion to the square of its
//! distance as it gets near) instead of asking for unbounded joint velocities; the other
//! components go on almost unchanged.
//!
//! **Within the limits**: when an axis would exceed its velocity, or come faster towards its
//! limit than it can still brake from ([`ramp::allowed_target`], the ramp's own envelope), the
//! whole vector is scaled down by the same factor, so that the TCP keeps the requested
//! direction, slower, and comes to rest where the first axis reaches its stop point.
//!
//! **Before a singularity** the same: a singularity measure is treated as a limit at
//! [`SINGULARITY_STOP_SHARE`] of its margin. When the motion brings a measure nearer to it
//! faster than the braking envelope from there allows (the rate of the measure from the
//! joint velocities; the elbow measure changes as fast as axis 3, the wrist measure as axis 5,
//! each braked as that axis is; the shoulder measure, a distance, at [`SHOULDER_BRAKE`]), the
//! whole vector is scaled down: the TCP slows along its direction and comes to rest there,
//! instead of being carried through the singularity by the ramp's momentum. Motion away from
//! it, or along it, is not held back by this.

use super::ramp::{self, RampLimits};
use mcm_kinematics::{Kinematics, Singularities, SingularityMargins};
use mcm_shared::NUM_AXES;
use mcm_shared::command::CartesianFrame;
use nalgebra::{Matrix6, Vector3, Vector6};

/// The damping factor at a singularity (`λ_max`, in the Jacobian's mixed units: metres for the
/// linear rows, 1 for the angular ones). Large against the smallest singular value a margin
/// leaves (about 0.03 at the P-Rob2's 5° elbow margin), small against the others (0.2 and
/// more), so that only the motion towards the singularity is held back.
pub const DAMPING_MAX: f64 = 0.05;

/// Where the slowing down before a singularity brings the arm to rest: this share of each
/// margin of [`SingularityMargins::DEFAULT`] (2.5 deg at the wrist and the elbow, 2.5 cm at
/// the shoulder).
pub const SINGULARITY_STOP_SHARE: f64 = 0.5;

/// The deceleration [m/s²] the slowing down before the shoulder singularity plans with for
/// its measure (the wrist centre's distance from axis 1).
pub const SHOULDER_BRAKE: f64 = 0.5;

/// Time step [s] of the rate of a singularity measure (its finite difference along the joint
/// velocities).
const RATE_STEP_S: f64 = 1e-4;

/// A TCP velocity as the core takes it: SI units, in `frame`'s axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Twist {
    /// The TCP origin's velocity [m/s].
    pub linear: [f64; 3],
    /// The TCP frame's angular velocity [rad/s].
    pub angular: [f64; 3],
    pub frame: CartesianFrame,
}

/// How near the nearest singularity is, as a share of its margin: 1 or more outside every
/// margin, 0 at a singularity.
/// A measure that is not a number counts as at the singularity.
pub fn margin_ratio(s: &Singularities, m: &SingularityMargins) -> f64 {
    let ratios = [
        s.wrist_rad / m.wrist_rad,
        s.elbow_rad / m.elbow_rad,
        s.shoulder_m / m.shoulder_m,
    ];
    if ratios.iter().any(|r| r.is_nan()) {
        return 0.0;
    }
    ratios.into_iter().fold(f64::INFINITY, f64::min).max(0.0)
}

/// `λ²` of the damped least squares at a margin ratio `r` ([`margin_ratio`]).
pub fn damping_squared(r: f64) -> f64 {
    let d = (1.0 - r).clamp(0.0, 1.0);
    DAMPING_MAX * DAMPING_MAX * d * d
}

/// The twist in the base frame at configuration `q` [rad]: `(linear, angular)`.
pub fn base_twist(kin: &Kinematics, q: &[f64; NUM_AXES], t: &Twist) -> Vector6<f64> {
    let (v, w) = (Vector3::from(t.linear), Vector3::from(t.angular));
    let (v, w) = match t.frame {
        CartesianFrame::Base => (v, w),
        CartesianFrame::Tool => {
            let r = kin.tcp_pose(q).rotation;
            (r * v, r * w)
        }
    };
    Vector6::new(v.x, v.y, v.z, w.x, w.y, w.z)
}

/// The joint velocities [rad/s] that give the TCP the twist `xi` (base frame) at `q`: exact
/// away from singularities, damped within their margins (module doc). Zeros when no finite
/// solution exists.
pub fn joint_velocities(kin: &Kinematics, q: &[f64; NUM_AXES], xi: &Vector6<f64>) -> Vector6<f64> {
    let j = kin.tcp_jacobian(q);
    let r = margin_ratio(&kin.singularities(q), &SingularityMargins::DEFAULT);
    let lambda2 = damping_squared(r);
    let solved = if lambda2 == 0.0 {
        j.lu().solve(xi)
    } else {
        let a = j * j.transpose() + Matrix6::identity() * lambda2;
        a.cholesky().map(|c| j.transpose() * c.solve(xi))
    };
    match solved {
        Some(qd) if qd.iter().all(|x| x.is_finite()) => qd,
        _ => Vector6::zeros(),
    }
}

/// `x` as a share from 0 to 1; 0 when not a number.
fn as_share(x: f64) -> f64 {
    if x.is_finite() {
        x.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The share (0 to 1) of `qd` that every axis's ramp allows at `q`: its velocity limit and its
/// braking envelope before its limits ([`ramp::allowed_target`]).
pub fn allowed_share(
    q: &[f64; NUM_AXES],
    qd: &Vector6<f64>,
    limits: &[RampLimits; NUM_AXES],
) -> f64 {
    let mut share: f64 = 1.0;
    for i in 0..NUM_AXES {
        let want = qd[i];
        if want != 0.0 {
            let allowed = ramp::allowed_target(q[i], want, &limits[i]);
            share = share.min(allowed / want);
        }
    }
    as_share(share)
}

/// The share (0 to 1) of `qd` with which no singularity measure approaches its stop point
/// ([`SINGULARITY_STOP_SHARE`] of its margin) faster than the braking envelope allows.
pub fn singularity_share(
    kin: &Kinematics,
    q: &[f64; NUM_AXES],
    qd: &Vector6<f64>,
    limits: &[RampLimits; NUM_AXES],
) -> f64 {
    let now = kin.singularities(q);
    let ahead = kin.singularities(&core::array::from_fn(|i| q[i] + qd[i] * RATE_STEP_S));
    let m = SingularityMargins::DEFAULT;
    let (wrist, elbow, shoulder) = (&limits[4], &limits[2], &limits[1]);
    let mut share: f64 = 1.0;
    for (now, ahead, margin, brake, lookahead_s) in [
        (
            now.wrist_rad,
            ahead.wrist_rad,
            m.wrist_rad,
            wrist.brake,
            wrist.lookahead_s,
        ),
        (
            now.elbow_rad,
            ahead.elbow_rad,
            m.elbow_rad,
            elbow.brake,
            elbow.lookahead_s,
        ),
        (
            now.shoulder_m,
            ahead.shoulder_m,
            m.shoulder_m,
            SHOULDER_BRAKE,
            shoulder.lookahead_s,
        ),
    ] {
        let approach = (now - ahead) / RATE_STEP_S;
        if approach > 0.0 {
            let distance = now - SINGULARITY_STOP_SHARE * margin;
            share = share.min(ramp::envelope(distance, brake, lookahead_s) / approach);
        }
    }
    as_share(share)
}

/// The joint velocity target [rad/s] of the TCP velocity `t` at the commanded configuration
/// `q` [rad]: [`base_twist`], [`joint_velocities`], scaled by the smaller of
/// [`allowed_share`] and [`singularity_share`].
pub fn joint_target(
    kin: &Kinematics,
    q: &[f64; NUM_AXES],
    t: &Twist,
    limits: &[RampLimits; NUM_AXES],
) -> [f64; NUM_AXES] {
    let qd = joint_velocities(kin, q, &base_twist(kin, q, t));
    let share = allowed_share(q, &qd, limits).min(singularity_share(kin, q, &qd, limits));
    core::array::from_fn(|i| qd[i] * share)
}

#[cfg(test)]
mod tests;
