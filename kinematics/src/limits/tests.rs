use super::*;
use std::f64::consts::PI;

const R170: AxisRange = AxisRange {
    min: -170.0 * PI / 180.0,
    max: 170.0 * PI / 180.0,
};

#[test]
fn an_angle_is_moved_by_whole_turns_into_the_range() {
    let d = f64::to_radians;
    let ok = |r: &AxisRange, a: f64, seed: f64| r.fit(0, d(a), d(seed)).map(f64::to_degrees);
    let near = |r: Result<f64, Miss>, want: f64| {
        let v = r.unwrap_or_else(|m| panic!("{want}: missed {m:?}"));
        assert!((v - want).abs() < 1e-9, "{v} != {want}");
    };
    near(ok(&R170, 30.0, 0.0), 30.0);
    near(ok(&R170, 390.0, 0.0), 30.0);
    near(ok(&R170, -330.0, 100.0), 30.0);
    near(ok(&R170, 200.0, 150.0), -160.0);
    // Within the tolerance of a limit: set onto it.
    let v = R170.fit(0, R170.max + 1e-10, R170.max).unwrap();
    assert_eq!(v, R170.max);
    // Outside on both sides of the range: the nearer miss is named.
    let m = ok(&R170, 175.0, 0.0).unwrap_err();
    assert!(
        (m.value.to_degrees() - 175.0).abs() < 1e-9 && (m.by.to_degrees() - 5.0).abs() < 1e-9,
        "{m:?}"
    );
    let m = ok(&R170, -179.0, 0.0).unwrap_err();
    assert!(
        (m.value.to_degrees() + 179.0).abs() < 1e-9 && (m.by.to_degrees() - 9.0).abs() < 1e-9,
        "{m:?}"
    );
}

/// An axis with more than a turn of range: of the angle's values within it, the one nearest
/// the seed; a seed far outside the range is as good as its nearer bound.
#[test]
fn a_range_of_more_than_a_turn_gives_the_value_nearest_the_seed() {
    let wide = AxisRange {
        min: -2.0 * PI,
        max: 2.0 * PI,
    };
    assert!((wide.fit(0, 1.0, 5.0).unwrap() - (1.0)).abs() < 1e-12);
    assert!((wide.fit(0, 1.0, -4.0).unwrap() - (1.0 - 2.0 * PI)).abs() < 1e-12);
    assert!((wide.fit(0, 1.0, 1e300).unwrap() - 1.0).abs() < 1e-12);
    assert!((wide.fit(0, 1.0, -1e300).unwrap() - (1.0 - 2.0 * PI)).abs() < 1e-12);
}

#[test]
fn travel_time_is_the_slowest_axis_at_full_speed() {
    let speed = [1.0, 2.0, 1.0, 4.0, 1.0, 1.0];
    let (t, _) = travel_time(&[0.0; 6], &[0.5, 1.8, 0.0, -2.0, 0.0, 0.1], &speed);
    assert!((t - 0.9).abs() < 1e-15, "{t}");
}
