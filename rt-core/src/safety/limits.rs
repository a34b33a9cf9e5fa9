//! Position and velocity limits per axis: [`PositionLimits`] and [`VelocityLimits`], the first
//! two of the per-cycle checks. Both run in the modes with a motion other than a planned one
//! (RELEASE, TORQUE_CONTROL, PVT, VELOCITY_CONTROL) and read the measured state.
//!
//! Runs inside the cycle (pure, allocation-free, panic-free; [`VelocityLimits::from_config`]
//! runs once at start). A position exactly at a limit is allowed; beyond it trips unless the
//! axis is at rest or moving back toward its range. A velocity whose magnitude exceeds
//! `overspeed_factor * max_velocity` trips. NaN or infinite values always trip.
//!
//! Parameters: the position limits `q_min`, `q_max` are the shared [`SafetyParams`]
//! (`axis.min_deg`, `axis.max_deg`; the braking check and the planners read them too); the trip
//! velocity is the velocity check's own, [`VelocityLimits::trip`]: `safety.overspeed_factor`
//! (`1..=`[`OVERSPEED_FACTOR_MAX`](mcm_shared::config::OVERSPEED_FACTOR_MAX)) x
//! `axis.max_velocity_deg_s` (`0 < x <=`
//! [`VELOCITY_MAX_DEG_S`](mcm_shared::config::VELOCITY_MAX_DEG_S)), the bounds checked when
//! the configuration is read.
//!
//! ```
//! use mcm_rt_core::safety::{check_position_limits_returning, Check, SafetyParams};
//! let p = SafetyParams::from_config(&mcm_shared::config::RobotConfig::prob2_default());
//! let mut q = [0.0; 6];
//! q[4] = p.q_min[4] - 1e-6;
//! let mut qd = [0.0; 6];
//! qd[4] = -0.1; // further out
//! let v = check_position_limits_returning(&p, &q, &qd).unwrap_err();
//! assert_eq!((v.check, v.axis, v.limit), (Check::PositionLimit, 4, p.q_min[4]));
//! qd[4] = 0.1; // back toward the range
//! assert_eq!(check_position_limits_returning(&p, &q, &qd), Ok(()));
//! ```

use super::{Check, CycleCheck, CycleInputs, SafetyParams, Situation, Violation, per_axis};
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;

/// The position limits on the measured state ([`check_position_limits_returning`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PositionLimits;

impl CycleCheck for PositionLimits {
    const ID: Check = Check::PositionLimit;

    fn runs(&self, now: &Situation) -> bool {
        now.free_motion_mode()
    }

    fn verdict(
        &mut self,
        params: &SafetyParams,
        inputs: &CycleInputs<'_>,
    ) -> Result<(), Violation> {
        check_position_limits_returning(params, inputs.position, inputs.velocity)
    }
}

/// The velocity limits on the measured velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VelocityLimits {
    /// The velocity above which an axis trips [rad/s] (0 for an axis missing from an
    /// unvalidated configuration: every motion trips).
    pub trip: [f64; NUM_AXES],
}

impl VelocityLimits {
    /// The trip velocities of a (validated) configuration: `safety.overspeed_factor` x
    /// `axis.max_velocity_deg_s`.
    pub fn from_config(cfg: &RobotConfig) -> VelocityLimits {
        let factor = cfg.safety.overspeed_factor;
        VelocityLimits {
            trip: per_axis(cfg, 0.0, |a| factor * a.max_velocity_deg_s.to_radians()),
        }
    }

    /// `Err` for the first axis with `|qd| > trip` (or not finite). `value` is the signed
    /// velocity, `limit` the trip velocity with the same sign.
    pub fn check(&self, qd: &[f64; NUM_AXES]) -> Result<(), Violation> {
        for (i, &v) in qd.iter().enumerate() {
            let lim = self.trip[i];
            if !v.is_finite() || v.abs() > lim {
                return Err(Violation {
                    check: Check::VelocityLimit,
                    axis: i,
                    value: v,
                    limit: if v < 0.0 { -lim } else { lim },
                });
            }
        }
        Ok(())
    }
}

impl CycleCheck for VelocityLimits {
    const ID: Check = Check::VelocityLimit;

    fn runs(&self, now: &Situation) -> bool {
        now.free_motion_mode()
    }

    fn verdict(
        &mut self,
        _shared: &SafetyParams,
        inputs: &CycleInputs<'_>,
    ) -> Result<(), Violation> {
        self.check(inputs.velocity)
    }
}

fn position_violation(axis: usize, value: f64, limit: f64) -> Violation {
    Violation {
        check: Check::PositionLimit,
        axis,
        value,
        limit,
    }
}

/// `Err` for the first axis outside `[q_min, q_max]` and not at rest or moving back toward its
/// range ("only jogs back toward the range allowed"), so that an arm pushed past a limit (e.g.
/// by hand in RELEASE) can be moved back. Beyond a limit and moving further out trips; a
/// non-finite position or velocity trips (then `limit` = `q_max`).
pub fn check_position_limits_returning(
    params: &SafetyParams,
    q: &[f64; NUM_AXES],
    qd: &[f64; NUM_AXES],
) -> Result<(), Violation> {
    for (i, (&x, &v)) in q.iter().zip(qd).enumerate() {
        if !(x.is_finite() && v.is_finite()) {
            return Err(position_violation(i, x, params.q_max[i]));
        }
        if x < params.q_min[i] && v < 0.0 {
            return Err(position_violation(i, x, params.q_min[i]));
        }
        if x > params.q_max[i] && v > 0.0 {
            return Err(position_violation(i, x, params.q_max[i]));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
