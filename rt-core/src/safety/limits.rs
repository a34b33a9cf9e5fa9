//! Position and velocity limits per axis.
//!
//! Runs inside the cycle (pure, allocation-free, panic-free). A position exactly at a limit
//! is allowed, beyond it trips; a velocity whose magnitude exceeds
//! `overspeed_factor * max_velocity` trips. NaN or infinite values always trip.
//!
//! ```
//! use mcm_rt_core::safety::{check_position_limits, Check, SafetyParams};
//! let p = SafetyParams::from_config(&mcm_shared::config::RobotConfig::prob2_default());
//! let mut q = [0.0; 6];
//! q[4] = p.q_min[4] - 1e-6;
//! let v = check_position_limits(&p, &q).unwrap_err();
//! assert_eq!((v.check, v.axis, v.limit), (Check::PositionLimit, 4, p.q_min[4]));
//! ```

use super::{Check, SafetyParams, Violation};
use mcm_shared::NUM_AXES;

fn position_violation(axis: usize, value: f64, limit: f64) -> Violation {
    Violation {
        check: Check::PositionLimit,
        axis,
        value,
        limit,
    }
}

/// `Err` for the first axis outside `[q_min, q_max]` (or not finite; then `limit` = `q_max`).
pub fn check_position_limits(params: &SafetyParams, q: &[f64; NUM_AXES]) -> Result<(), Violation> {
    for (i, &x) in q.iter().enumerate() {
        if x < params.q_min[i] {
            return Err(position_violation(i, x, params.q_min[i]));
        }
        if !x.is_finite() || x > params.q_max[i] {
            return Err(position_violation(i, x, params.q_max[i]));
        }
    }
    Ok(())
}

/// Like [`check_position_limits`], but an axis beyond a limit that is at rest or moving back
/// toward its range is allowed ("only jogs back toward the range allowed"), so that an arm
/// pushed past a limit (e.g. by hand in RELEASE) can be moved back. Beyond a limit and moving
/// further out trips; a non-finite position or velocity trips.
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

/// `Err` for the first axis with `|qd| > v_trip` (or not finite). `value` is the signed
/// velocity, `limit` the trip velocity with the same sign.
pub fn check_velocity_limits(params: &SafetyParams, qd: &[f64; NUM_AXES]) -> Result<(), Violation> {
    for (i, &v) in qd.iter().enumerate() {
        let lim = params.v_trip[i];
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

#[cfg(test)]
mod tests;
