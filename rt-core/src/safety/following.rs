//! Following error: the actual position must stay within a band around the commanded one
//! (manual: applies in HOLD and PVT). Also catches collisions and blocked axes.
//!
//! Runs inside the cycle (pure, allocation-free, panic-free). An error exactly equal to the
//! band is allowed; NaN or infinite positions trip.
//!
//! ```
//! use mcm_rt_core::safety::{check_following_error, SafetyParams};
//! use mcm_shared::reply::Reason;
//! let p = SafetyParams::from_config(&mcm_shared::config::RobotConfig::prob2_default());
//! let cmd = [0.0; 6];
//! let mut act = [0.0; 6];
//! act[2] = -2.5f64.to_radians(); // band is 2 deg
//! let v = check_following_error(&p, &cmd, &act).unwrap_err();
//! assert_eq!(v.axis, 2);
//! let Reason::FollowingError { error_deg, band_deg, .. } = v.reason() else { panic!() };
//! assert!((error_deg - 2.5).abs() < 1e-9 && (band_deg - 2.0).abs() < 1e-9);
//! ```

use super::{Check, SafetyParams, Violation};
use mcm_shared::NUM_AXES;

/// `Err` for the first axis with `|commanded - actual| > following_band` (or not finite);
/// `value` = `|commanded - actual|` [rad], `limit` = the band [rad].
pub fn check_following_error(
    params: &SafetyParams,
    commanded: &[f64; NUM_AXES],
    actual: &[f64; NUM_AXES],
) -> Result<(), Violation> {
    for (i, (&c, &a)) in commanded.iter().zip(actual).enumerate() {
        let err = (c - a).abs();
        // inf - inf is NaN; one infinite side gives inf.
        if err.is_nan() || err > params.following_band[i] {
            return Err(Violation {
                check: Check::FollowingError,
                axis: i,
                value: err,
                limit: params.following_band[i],
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
