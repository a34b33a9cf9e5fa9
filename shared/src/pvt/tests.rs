use super::*;

#[test]
fn reachable_points_pass_and_the_first_broken_limit_is_named() {
    let l = PointLimits::from_config(&RobotConfig::prob2_default());
    assert_eq!(check_point(&[0.0; 6], &[0.0; 6], &l), Ok(()));
    let mut q = [0.0; 6];
    q[2] = l.reach_max[2] + 1e-6;
    let mut v = [0.0; 6];
    v[0] = l.velocity[0] * 1.01;
    // Axis 1's speed comes before axis 3's position.
    let e = check_point(&q, &v, &l).unwrap_err();
    assert_eq!((e.axis, e.what), (0, PvtQuantity::Velocity));
    let e = check_point(&q, &[0.0; 6], &l).unwrap_err();
    assert_eq!(
        (e.axis, e.what, e.limit),
        (2, PvtQuantity::Position, l.reach_max[2])
    );
    q[2] = f64::NAN;
    let e = check_point(&q, &[0.0; 6], &l).unwrap_err();
    assert_eq!((e.axis, e.limit), (2, l.reach_min[2]));
}
