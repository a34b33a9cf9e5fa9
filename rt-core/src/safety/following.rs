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
mod tests {
    use super::*;
    use mcm_shared::config::RobotConfig;

    const EPS: f64 = 1e-9;

    fn params() -> SafetyParams {
        SafetyParams::from_config(&RobotConfig::prob2_default())
    }

    #[test]
    fn just_inside_and_outside_the_band_on_each_axis_both_directions() {
        let p = params();
        let cmd = [0.3, -0.2, 1.0, -1.5, 0.7, 2.0];
        for i in 0..6 {
            let band = p.following_band[i];
            for s in [1.0, -1.0] {
                let mut act = cmd;
                act[i] = cmd[i] + s * (band - EPS);
                assert_eq!(check_following_error(&p, &cmd, &act), Ok(()));
                act[i] = cmd[i] + s * (band + EPS);
                let e = check_following_error(&p, &cmd, &act).unwrap_err();
                assert_eq!((e.check, e.axis, e.limit), (Check::FollowingError, i, band));
                assert!((e.value - (band + EPS)).abs() < 1e-12);
            }
        }
        assert_eq!(check_following_error(&p, &cmd, &cmd), Ok(()));
    }

    #[test]
    fn non_finite_positions_trip() {
        let p = params();
        for i in 0..6 {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut x = [0.0; 6];
                x[i] = bad;
                let e = check_following_error(&p, &x, &[0.0; 6]).unwrap_err();
                assert_eq!((e.check, e.axis), (Check::FollowingError, i));
                let e = check_following_error(&p, &[0.0; 6], &x).unwrap_err();
                assert_eq!(e.axis, i);
                // Both sides the same infinity is not "no error".
                assert!(check_following_error(&p, &x, &x).is_err());
            }
        }
    }
}
