//! # Straight-line motion of the TCP (`move_linear`)
//!
//! [`LinePlan::plan`] plans a move of the TCP on the straight line from where the arm rests
//! to a target position, the orientation turned on the shortest arc to the target's (or kept),
//! and checks the whole path before anything moves; [`LinePlan::sample`] gives the joint
//! values and velocities at any time of the move. Both are allocation-free and bounded (no
//! loop whose length depends on the input beyond [`MAX_INTERVALS`]), so both may run inside
//! the control cycle.
//!
//! **The path.** The pose at the path parameter s ∈ [0, 1]: the position p₀ + s·(p₁ − p₀),
//! the orientation R₀·exp(s·w) with w the rotation vector of R₀⁻¹R₁ (angle at most 180°: the
//! shortest arc). Its derivative along s is one constant twist ξ = (p₁ − p₀, R₀w): the TCP's
//! velocity is ξ·ds/dt.
//!
//! **The check** (module `check`): the path is sampled every [`STEP_M`] (1 mm) of TCP
//! travel and every [`STEP_DEG`] (0.5°) of turn, whichever gives more points, in a multiple
//! of [`KNOTS`] intervals, at most [`MAX_INTERVALS`] (so the spacing is 1 mm up to a 2.048 m
//! path). At each point the inverse kinematics of the start's [`Branch`], continued from the
//! previous point; each axis within its reachable range; the joint rates dq/ds = J⁻¹ξ.
//! Between two points, from the values and rates at both ends: no jump, no axis turning
//! beyond its range, each singularity measure at least its margin
//! ([`crate::SingularityMargins::DEFAULT`]) all the way (the module `check` says how). The
//! first failure is the error, naming where.
//!
//! **The time law** (modules `scaling` and `profile`): for each checked interval the largest
//! ds/dt, d²s/dt² and d³s/dt³ that keep the TCP's speed and acceleration within the request,
//! its angular speed and acceleration within the request divided by [`ROTATION_RADIUS_M`],
//! and every axis within its velocity, acceleration and jerk limits there; the intervals
//! gathered into at most [`MAX_SEGMENTS`] segments, each with the smallest bounds of its
//! intervals; s(t) crosses each segment with a jerk-limited ramp (a constant acceleration
//! when no axis has a jerk limit) to a cruise and a ramp to the next segment's speed, the
//! speeds where segments meet from a backward and a forward pass. So the pace follows the
//! path: slow only where the path is demanding (near a singularity or the edge of the reach).

mod check;
mod error;
mod profile;
mod scaling;

pub use error::{LineError, PathPoint, Singularity};

use crate::{Branch, Kinematics, N};
use mcm_shared::command::MoveLinear;
use mcm_shared::config::RobotConfig;
use nalgebra::{Isometry3, Matrix6, UnitQuaternion, Vector3, Vector6};
pub use profile::MAX_SEGMENTS;
use profile::PathProfile;
use scaling::Pace;

/// The largest TCP travel between two checked points of the path [m].
pub const STEP_M: f64 = 0.001;
/// The largest turn of the TCP between two checked points of the path [deg].
pub const STEP_DEG: f64 = 0.5;
/// The path is divided into a multiple of this many intervals; the plan keeps the joint values
/// at these `KNOTS + 1` points (the seeds of [`LinePlan::sample`]).
pub const KNOTS: usize = 64;
/// The most intervals the path is checked in (the planner's bound on its work).
pub const MAX_INTERVALS: usize = 2048;

/// The TCP speed when the request gives none [m/s] (the contract's), and the most it may ask
/// for.
pub const DEFAULT_VELOCITY_M_S: f64 = MoveLinear::DEFAULT_VELOCITY_M_S;
pub const MAX_VELOCITY_M_S: f64 = 1.0;
/// The TCP acceleration when the request gives none [m/s²] (the contract's), and the most it
/// may ask for.
pub const DEFAULT_ACCELERATION_M_S2: f64 = MoveLinear::DEFAULT_ACCELERATION_M_S2;
pub const MAX_ACCELERATION_M_S2: f64 = 10.0;
/// The rotation's speed limit: the TCP turns at most at the requested speed divided by this
/// radius (rad/s per m/s), its angular acceleration at most the requested acceleration
/// divided by it: a point of the tool this far from the TCP (a gripper's fingertips) moves no
/// faster than the TCP may [m]. 0.25 m/s gives 2.5 rad/s (143°/s).
pub const ROTATION_RADIUS_M: f64 = 0.1;

/// Each axis's velocity [rad/s], acceleration [rad/s²] and jerk [rad/s³] limit (`None`: no
/// jerk limit), from the configuration's `max_velocity_deg_s`, `max_acceleration_deg_s2`,
/// `max_jerk_deg_s3` (checked when it is loaded).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointLimits {
    pub velocity: [f64; N],
    pub acceleration: [f64; N],
    pub jerk: [Option<f64>; N],
}

impl JointLimits {
    /// The configured limits, in radians. `None` when the configuration has not six axes.
    pub fn from_config(cfg: &RobotConfig) -> Option<JointLimits> {
        let axes: &[_; N] = cfg.axes.as_slice().try_into().ok()?;
        Some(JointLimits {
            velocity: axes.each_ref().map(|a| a.max_velocity_deg_s.to_radians()),
            acceleration: axes
                .each_ref()
                .map(|a| a.max_acceleration_deg_s2.to_radians()),
            jerk: axes
                .each_ref()
                .map(|a| a.max_jerk_deg_s3.map(f64::to_radians)),
        })
    }
}

impl JointLimits {
    /// Every limit finite and above 0 (the configuration's are), else the first that is not.
    fn check(&self) -> Result<(), LineError> {
        for axis in 0..N {
            for (name, value) in [
                ("velocity", self.velocity[axis]),
                ("acceleration", self.acceleration[axis]),
                ("jerk", self.jerk[axis].unwrap_or(1.0)),
            ] {
                if !(value.is_finite() && value > 0.0) {
                    return Err(LineError::Limit {
                        axis: axis + 1,
                        name,
                        value,
                    });
                }
            }
        }
        Ok(())
    }
}

/// Where `move_linear` goes: the TCP's target position [m] and orientation (base frame;
/// `None`: the start's kept), the TCP's speed [m/s] and acceleration [m/s²] (`None`:
/// [`DEFAULT_VELOCITY_M_S`], [`DEFAULT_ACCELERATION_M_S2`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineTarget {
    pub position: Vector3<f64>,
    pub orientation: Option<UnitQuaternion<f64>>,
    pub velocity: Option<f64>,
    pub acceleration: Option<f64>,
}

/// The joint values [rad] and velocities [rad/s] at one instant of a line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineSample {
    pub q: [f64; N],
    pub qdot: [f64; N],
}

/// A planned, checked straight-line move. Plain data (`Copy`, no heap, about 13 KB): the
/// kinematics it was planned with (the TCP included), the path, the time law (how each of at
/// most [`MAX_SEGMENTS`] segments is crossed) and the joint values at [`KNOTS`] + 1 points of
/// the path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinePlan {
    kin: Kinematics,
    branch: Branch,
    start: Isometry3<f64>,
    /// The path's derivative along s: the TCP's displacement and its rotation vector in the
    /// base frame.
    twist: Vector6<f64>,
    /// The rotation vector of R₀⁻¹R₁ (the turn in the start's frame) [rad].
    turn: Vector3<f64>,
    profile: PathProfile,
    knots: [[f64; N]; KNOTS + 1],
    joint_target: [f64; N],
}

impl LinePlan {
    /// Plan the line from the configuration `start` [rad] (the arm at rest) to `target`,
    /// within the axes' `limits`, the singularity margins
    /// [`crate::SingularityMargins::DEFAULT`]: the whole path checked and time-scaled (the
    /// module's doc). Refused with a [`LineError`] naming what and where; nothing is planned
    /// then. Allocation-free; at most [`MAX_INTERVALS`] + 1 points checked.
    pub fn plan(
        kin: &Kinematics,
        limits: &JointLimits,
        start: &[f64; N],
        target: &LineTarget,
    ) -> Result<LinePlan, LineError> {
        let finite =
            |what: &'static str, values: &[f64]| match values.iter().find(|v| !v.is_finite()) {
                None => Ok(()),
                Some(&value) => Err(LineError::NotFinite { what, value }),
            };
        finite("start configuration", start)?;
        finite("target position", target.position.as_slice())?;
        if let Some(o) = &target.orientation {
            finite("target orientation", o.coords.as_slice())?;
        }
        limits.check()?;
        let velocity = argument(
            "velocity",
            target.velocity,
            DEFAULT_VELOCITY_M_S,
            MAX_VELOCITY_M_S,
            "m/s",
        )?;
        let acceleration = argument(
            "acceleration",
            target.acceleration,
            DEFAULT_ACCELERATION_M_S2,
            MAX_ACCELERATION_M_S2,
            "m/s^2",
        )?;
        let start_pose = kin.tcp_pose(start);
        let r0 = start_pose.rotation;
        let turn = (r0.inverse() * target.orientation.unwrap_or(r0)).scaled_axis();
        let displacement = target.position - start_pose.translation.vector;
        let mut twist = Vector6::zeros();
        twist.fixed_rows_mut::<3>(0).copy_from(&displacement);
        twist.fixed_rows_mut::<3>(3).copy_from(&(r0 * turn));
        let mut plan = LinePlan {
            kin: *kin,
            branch: kin.branch(start),
            start: start_pose,
            twist,
            turn,
            profile: PathProfile::default(),
            knots: [*start; KNOTS + 1],
            joint_target: *start,
        };
        let twist = plan.twist;
        plan.profile = check::walk(&mut plan, start, |h| {
            Pace::new(limits, velocity, acceleration, &twist, h)
        })?;
        Ok(plan)
    }

    /// The move's duration [s].
    pub fn duration(&self) -> f64 {
        self.profile.duration()
    }

    /// The joint values at the end [rad]: the start's branch at the target.
    pub fn joint_target(&self) -> [f64; N] {
        self.joint_target
    }

    /// The branch of the solution the whole move stays on (the start's).
    pub fn branch(&self) -> Branch {
        self.branch
    }

    /// The TCP's pose at the path parameter `s` (0: the start, 1: the target; clamped).
    pub fn pose_at(&self, s: f64) -> Isometry3<f64> {
        let s = if s.is_nan() { 0.0 } else { s.clamp(0.0, 1.0) };
        let p = self.start.translation.vector + s * self.twist.fixed_rows::<3>(0);
        Isometry3::from_parts(
            p.into(),
            self.start.rotation * UnitQuaternion::from_scaled_axis(s * self.turn),
        )
    }

    /// The path parameter s, ds/dt [1/s] and d²s/dt² [1/s²] at `t` seconds after the start.
    pub fn path_at(&self, t: f64) -> (f64, f64, f64) {
        self.profile.sample(t)
    }

    /// The joint values and velocities `t` seconds after the start: the inverse kinematics of
    /// the plan's branch at the pose of s(t), continued from the nearest of the plan's
    /// [`KNOTS`] + 1 stored points; the velocities J⁻¹·ξ·ds/dt. Before the start the start, from
    /// the end on exactly [`LinePlan::joint_target`] at rest. Allocation-free, a bounded amount
    /// of work (a binary search of the time law's segments, one branch of the inverse
    /// kinematics, one 6×6 solve).
    ///
    /// The planner checked the inverse kinematics at every point of the path, so it does not
    /// fail here; should rounding make it fail, the joint values are interpolated between the
    /// two stored points around s instead (and the velocities are zero where the Jacobian
    /// cannot be inverted, which the margins exclude).
    pub fn sample(&self, t: f64) -> LineSample {
        if t >= self.duration() {
            return LineSample {
                q: self.joint_target,
                qdot: [0.0; N],
            };
        }
        let (s, sdot, _) = self.profile.sample(t);
        let x = s * KNOTS as f64;
        let below = (x.floor() as usize).min(KNOTS - 1);
        let seed = &self.knots[(x.round() as usize).min(KNOTS)];
        let q = self
            .kin
            .inverse_branch(&self.pose_at(s), self.branch, seed)
            .unwrap_or_else(|_| {
                let f = x - below as f64;
                let (a, b) = (&self.knots[below], &self.knots[below + 1]);
                core::array::from_fn(|i| a[i] + f * (b[i] - a[i]))
            });
        let rate = joint_rates(&self.kin.tcp_jacobian(&q), &self.twist).unwrap_or_default();
        LineSample {
            q,
            qdot: core::array::from_fn(|i| rate[i] * sdot),
        }
    }
}

/// dq/ds = J⁻¹·ξ; `None` where J is singular.
fn joint_rates(jacobian: &Matrix6<f64>, twist: &Vector6<f64>) -> Option<Vector6<f64>> {
    jacobian.lu().solve(twist)
}

/// A requested speed or acceleration, or its default; refused outside (0, max].
fn argument(
    name: &'static str,
    value: Option<f64>,
    default: f64,
    max: f64,
    unit: &'static str,
) -> Result<f64, LineError> {
    match value {
        None => Ok(default),
        Some(v) if v > 0.0 && v <= max => Ok(v),
        Some(value) => Err(LineError::Argument {
            name,
            value,
            max,
            unit,
        }),
    }
}

#[cfg(test)]
mod tests;
