use super::*;
use crate::config::RobotConfig;

#[test]
fn every_argument_has_one_row_and_a_unique_name_and_code() {
    for (i, s) in ARGS.iter().enumerate() {
        assert_eq!(s.arg.spec(), s, "{}", s.name);
        assert_eq!(Arg::by_name(s.name), Some(s.arg));
        assert_eq!(Arg::from_code(s.arg as u32), Some(s.arg));
        for t in &ARGS[i + 1..] {
            assert_ne!(s.name, t.name);
            assert_ne!(s.arg, t.arg);
        }
    }
    assert_eq!(Arg::from_code(0), None);
    assert_eq!(Arg::by_name("nope"), None);
}

#[test]
fn numbers_are_readable() {
    let cases = [
        (0.0, "0"),
        (-0.0, "0"),
        (169.0, "169"),
        (-169.00000000000003, "-169"),
        (175.0, "175"),
        (0.5, "0.5"),
        (0.001, "0.001"),
        (129.60000000000002, "129.6"),
        (1.0000000001, "1.0000000001"),
        (1e-320, "1e-320"),
        (5e-324, "5e-324"),
        (1e-6, "1e-6"),
        (0.00001, "0.00001"),
        (2.5e20, "2.5e20"),
        (f64::MAX, "1.79769313486e308"),
        (f64::NAN, "NaN"),
        (f64::NEG_INFINITY, "-inf"),
    ];
    for (x, text) in cases {
        assert_eq!(Num(x).to_string(), text, "{x:e}");
    }
}

#[test]
fn the_reachable_range_is_the_limits_less_the_margin() {
    let cfg = RobotConfig::prob2_default();
    assert_eq!(reachable_deg(&cfg, 0), (-169.0, 169.0));
    assert_eq!(Arg::TargetPosition.bounds(&cfg, Some(0)), (-169.0, 169.0));
    assert_eq!(Arg::Dt.bounds(&cfg, None), (0.005, 1.0));
    let peak = peak_torque_nm(&cfg, 0);
    assert_eq!(Arg::Torques.bounds(&cfg, Some(0)), (-peak, peak));
    assert_eq!(Arg::Velocities.bounds(&cfg, Some(1)), (-90.0, 90.0));
    assert_eq!(Arg::Velocities.bounds(&cfg, Some(3)), (-150.0, 150.0));
    let r = Arg::Velocities
        .check(151.0, Arg::Velocities.bounds(&cfg, Some(3)), Axis::new(4))
        .unwrap_err();
    assert_eq!(
        r.to_string(),
        "argument \"velocities[3]\" = 151 is not allowed; expected a number from -150 to 150 \
         deg/s (the axis's maximum velocity)"
    );
}

#[test]
fn refusals_name_the_argument_the_value_and_the_range() {
    let cfg = RobotConfig::prob2_default();
    let axis1 = Axis::new(1);
    let e = Arg::TargetPosition
        .check(175.0, Arg::TargetPosition.bounds(&cfg, Some(0)), axis1)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "argument \"target_position\" = 175 is not allowed; expected a number from -169 to 169 \
         deg (the axis's reachable range: its limits less the safety margin)"
    );
    let e = Arg::Torques
        .check(-200.0, (-129.6, 129.6), Axis::new(3))
        .unwrap_err();
    assert!(
        e.to_string()
            .starts_with("argument \"torques[2]\" = -200 is not allowed"),
        "{e}"
    );
    let vf = Arg::VelocityFactor;
    for x in [0.0, 1e-320, 0.0009, 1.0000001, f64::NAN] {
        assert!(vf.check(x, vf.fixed_bounds(), None).is_err(), "{x}");
    }
    for x in [0.001, 0.5, 1.0] {
        assert_eq!(vf.check(x, vf.fixed_bounds(), None), Ok(x));
    }
    assert_eq!(
        vf.check(1e-320, vf.fixed_bounds(), None)
            .unwrap_err()
            .to_string(),
        "argument \"velocity_factor\" = 1e-320 is not allowed; expected a number from 0.001 to 1 \
         (a fraction of each axis's maximum velocity)"
    );
    let t = Arg::Timeout;
    assert!(t.check(0.0, t.fixed_bounds(), None).is_err());
    assert!(t.check(-5.0, t.fixed_bounds(), None).is_ok());
    assert_eq!(
        t.expected(-f64::MAX, 3600.0).to_string(),
        "a number other than 0, at most 3600 s (negative: no timeout)"
    );
    let a = Arg::AxisIndex;
    assert!(a.check(2.5, a.fixed_bounds(), None).is_err());
    assert_eq!(
        a.expected(1.0, 6.0).to_string(),
        "an axis number from 1 to 6"
    );
    assert_eq!(Arg::TargetPosition.fixed_bounds().0, f64::NEG_INFINITY);
}
