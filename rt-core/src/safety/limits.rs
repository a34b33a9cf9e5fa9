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
mod tests {
    use super::*;
    use mcm_shared::config::RobotConfig;

    const EPS: f64 = 1e-9;

    fn params() -> SafetyParams {
        SafetyParams::from_config(&RobotConfig::prob2_default())
    }

    fn one(axis: usize, x: f64) -> [f64; 6] {
        let mut a = [0.0; 6];
        a[axis] = x;
        a
    }

    #[test]
    fn position_just_inside_and_outside_each_limit_of_each_axis() {
        let p = params();
        for i in 0..6 {
            for (lim, out) in [(p.q_max[i], 1.0), (p.q_min[i], -1.0)] {
                assert_eq!(check_position_limits(&p, &one(i, lim - out * EPS)), Ok(()));
                assert_eq!(
                    check_position_limits(&p, &one(i, lim)),
                    Ok(()),
                    "at the limit"
                );
                let x = lim + out * EPS;
                assert_eq!(
                    check_position_limits(&p, &one(i, x)),
                    Err(position_violation(i, x, lim))
                );
            }
        }
    }

    #[test]
    fn velocity_just_inside_and_outside_in_both_directions_on_each_axis() {
        let p = params();
        for i in 0..6 {
            let lim = p.v_trip[i];
            assert!(lim > p.v_max[i]);
            for s in [1.0, -1.0] {
                assert_eq!(check_velocity_limits(&p, &one(i, s * (lim - EPS))), Ok(()));
                let v = s * (lim + EPS);
                let err = check_velocity_limits(&p, &one(i, v)).unwrap_err();
                assert_eq!(
                    (err.check, err.axis, err.value, err.limit),
                    (Check::VelocityLimit, i, v, s * lim)
                );
            }
        }
    }

    #[test]
    fn non_finite_values_trip() {
        let p = params();
        for i in 0..6 {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let e = check_position_limits(&p, &one(i, bad)).unwrap_err();
                assert_eq!((e.check, e.axis), (Check::PositionLimit, i));
                let e = check_velocity_limits(&p, &one(i, bad)).unwrap_err();
                assert_eq!((e.check, e.axis), (Check::VelocityLimit, i));
                let e = check_position_limits_returning(&p, &one(i, bad), &[0.0; 6]).unwrap_err();
                assert_eq!(e.axis, i);
                let e = check_position_limits_returning(&p, &[0.0; 6], &one(i, bad)).unwrap_err();
                assert_eq!(e.axis, i);
            }
        }
    }

    #[test]
    fn beyond_a_limit_only_moving_back_is_allowed() {
        let p = params();
        for i in 0..6 {
            let above = one(i, p.q_max[i] + 0.01);
            let below = one(i, p.q_min[i] - 0.01);
            assert_eq!(
                check_position_limits_returning(&p, &above, &one(i, -0.1)),
                Ok(())
            );
            assert_eq!(
                check_position_limits_returning(&p, &above, &[0.0; 6]),
                Ok(())
            );
            assert!(check_position_limits_returning(&p, &above, &one(i, 0.1)).is_err());
            assert_eq!(
                check_position_limits_returning(&p, &below, &one(i, 0.1)),
                Ok(())
            );
            assert!(check_position_limits_returning(&p, &below, &one(i, -0.1)).is_err());
            // Inside the range every direction is fine.
            assert_eq!(
                check_position_limits_returning(&p, &[0.0; 6], &one(i, 0.5)),
                Ok(())
            );
        }
    }
}
