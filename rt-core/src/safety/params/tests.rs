use super::*;

#[test]
fn prob2_values_in_si() {
    let cfg = RobotConfig::prob2_default();
    let p = SafetyParams::from_config(&cfg);
    let d = |x: f64| x.to_radians();
    assert_eq!(p.cycle_s, 0.005);
    assert!((p.reaction_s - 0.010).abs() < 1e-15);
    assert!((p.margin - d(1.0)).abs() < 1e-15);
    assert!((p.q_min[1] - d(-120.0)).abs() < 1e-15 && (p.q_max[2] - d(135.0)).abs() < 1e-15);
    assert!((p.brake_decel[3] - 0.8 * d(300.0)).abs() < 1e-12);
    assert_eq!(
        (p.rated_current[0], p.max_current[0], p.derated_current[0]),
        (4.0, 10.0, 4.0)
    );
    assert_eq!(p.i2t_tau[4], 20.0);
    assert!(p.stop_jerk.iter().all(|j| j.is_infinite()));
    assert_eq!(p.braking_latency_s(0), p.reaction_s);
    assert_eq!(p.braking_latency_s(6), f64::INFINITY);
}

#[test]
fn jerk_limited_stop_adds_ramp_time() {
    let cfg = RobotConfig::prob2_default();
    let p = SafetyParams::from_config(&cfg).with_jerk_limited_stop(&cfg);
    // a_b = 144 deg/s^2, j = 1800 deg/s^3 -> a_b / (2 j) = 0.04 s.
    assert!((p.braking_latency_s(0) - (0.010 + 0.04)).abs() < 1e-12);
}
