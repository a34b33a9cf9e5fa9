use super::*;
use mcm_shared::config::RobotConfig;

const EPS: f64 = 1e-9;

fn params() -> SafetyParams {
    SafetyParams::from_config(&RobotConfig::prob2_default())
}

fn velocity() -> VelocityLimits {
    VelocityLimits::from_config(&RobotConfig::prob2_default())
}

#[test]
fn prob2_trip_velocities_in_si() {
    // overspeed_factor 1.1 x max_velocity_deg_s 90 on axis 1.
    assert!((velocity().trip[0] - 1.1 * 90f64.to_radians()).abs() < 1e-12);
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
            // Moving outwards: inside and at the limit pass, beyond it trips.
            let qd = one(i, out * 0.1);
            assert_eq!(
                check_position_limits_returning(&p, &one(i, lim - out * EPS), &qd),
                Ok(())
            );
            assert_eq!(
                check_position_limits_returning(&p, &one(i, lim), &qd),
                Ok(()),
                "at the limit"
            );
            let x = lim + out * EPS;
            assert_eq!(
                check_position_limits_returning(&p, &one(i, x), &qd),
                Err(position_violation(i, x, lim))
            );
        }
    }
}

#[test]
fn velocity_just_inside_and_outside_in_both_directions_on_each_axis() {
    let p = params();
    let limits = velocity();
    for i in 0..6 {
        let lim = limits.trip[i];
        assert!(lim > p.v_max[i]);
        for s in [1.0, -1.0] {
            assert_eq!(limits.check(&one(i, s * (lim - EPS))), Ok(()));
            let v = s * (lim + EPS);
            let err = limits.check(&one(i, v)).unwrap_err();
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
            let e = check_position_limits_returning(&p, &one(i, bad), &[0.0; 6]).unwrap_err();
            assert_eq!((e.check, e.axis), (Check::PositionLimit, i));
            let e = velocity().check(&one(i, bad)).unwrap_err();
            assert_eq!((e.check, e.axis), (Check::VelocityLimit, i));
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
