use super::*;

fn limits() -> AxisLimits {
    AxisLimits {
        min: -1.0,
        max: 1.0,
        min_deg: -1f64.to_degrees(),
        max_deg: 1f64.to_degrees(),
        velocity: 20.0,
        acceleration: 1e4,
        velocity_deg: 20f64.to_degrees(),
    }
}

fn knot(p: f64, v: f64) -> Knot {
    Knot { p, v, a: None }
}

#[test]
fn a_segment_that_overshoots_between_its_points_is_caught() {
    // Both points in range; the cubic between them turns at about 1.02.
    let e = segment(knot(0.98, 12.0), knot(0.99, 0.0), 0.01, &limits()).unwrap_err();
    assert_eq!(e.0, Quantity::Position);
    assert!(e.1 > 1.0 && e.2 > 0.0 && e.2 < 0.01, "{e:?}");
    let mut wider = limits();
    wider.max = 1.01;
    assert!(segment(knot(0.98, 12.0), knot(0.99, 0.0), 0.01, &wider).is_ok());
}

#[test]
fn speed_between_points_and_acceleration_at_the_ends_are_caught() {
    // 0.19 rad in 0.01 s from 19 rad/s to 19 rad/s: the speed peaks between the points.
    let e = segment(knot(0.0, 19.0), knot(0.19, 19.0), 0.01, &limits());
    assert!(e.is_ok(), "straight at 19 rad/s: {e:?}");
    let e = segment(knot(0.0, 19.0), knot(0.2, 19.0), 0.01, &limits()).unwrap_err();
    assert_eq!(e.0, Quantity::Velocity);
    assert!(e.1 > 20.0 && e.2 > 0.0 && e.2 < 0.01, "{e:?}");
    // From rest to rest over 0.02 rad in 0.01 s: 6·0.02/0.01² = 1200 rad/s² at the start.
    let mut l = limits();
    l.acceleration = 1000.0;
    let e = segment(knot(0.0, 0.0), knot(0.02, 0.0), 0.01, &l).unwrap_err();
    assert_eq!(e.0, Quantity::Acceleration);
    assert!((e.1 - 1200.0).abs() < 1e-6 && e.2 == 0.0, "{e:?}");
}

#[test]
fn roots_of_quadratics() {
    let mut r = roots(1.0, -3.0, 2.0).map(|x| x.unwrap());
    r.sort_by(f64::total_cmp);
    assert_eq!(r, [1.0, 2.0]);
    assert_eq!(roots(0.0, 2.0, -1.0), [Some(0.5), None]);
    assert_eq!(roots(1.0, 0.0, 1.0), [None, None]);
    assert_eq!(roots(0.0, 0.0, 1.0), [None, None]);
}
