use super::*;
use proptest::prelude::*;

const DEG: f64 = std::f64::consts::PI / 180.0;

#[test]
fn distances_match_the_reference_table() {
    // (v, a, j, d2, d3) in degrees, worked out by hand from the module doc's formulas.
    let table = [
        (90.0, 180.0, 1800.0, 22.5, 27.0),
        (30.0, 180.0, 1800.0, 2.5, 4.0),
        (150.0, 360.0, 3600.0, 31.25, 38.75),
    ];
    for (v, a, j, d2, d3) in table {
        for sign in [1.0, -1.0] {
            let (v, a, j) = (sign * v * DEG, a * DEG, j * DEG);
            assert!((stopping_distance(v, a, None) - d2 * DEG).abs() < 1e-12);
            assert!((stopping_distance(v, a, Some(j)) - d3 * DEG).abs() < 1e-12);
            assert!((stopping_distance_from(v, 0.0, a, Some(j)) - sign * d3 * DEG).abs() < 1e-12);
        }
    }
    // Triangular deceleration (v·J < D²): v^{3/2}/√J.
    assert!((stopping_distance(0.01, 1.0, Some(1.0)) - 0.001).abs() < 1e-15);
}

#[test]
fn bad_input_is_conservative_or_typed() {
    assert_eq!(stopping_distance(1.0, 0.0, None), f64::INFINITY);
    assert_eq!(stopping_distance(f64::NAN, 1.0, None), f64::INFINITY);
    assert_eq!(stopping_distance(1.0, 1.0, Some(-1.0)), f64::INFINITY);
    assert_eq!(stopping_distance(0.0, 1.0, Some(1.0)), 0.0);
    let p = [0.5; 6];
    let mut decel = [2.0; 6];
    decel[3] = f64::NAN;
    let e = StopPlan::try_plan_from_state(p, [1.0; 6], [0.0; 6], decel, [None; 6]).unwrap_err();
    assert!(matches!(e, StopError::Deceleration { axis: 3, .. }));
    assert!(e.to_string().contains("axis index 3") && e.to_string().contains("finite and > 0"));
    let stop = StopPlan::plan_from_state(p, [1.0; 6], [0.0; 6], decel, [Some(-5.0); 6]);
    assert_eq!(stop.sample(0.0).position[3], 0.5); // stopped at once
    assert_eq!(stop.sample(0.0).velocity[3], 0.0);
    assert!((stop.duration() - 0.5).abs() < 1e-12); // invalid jerk ignored: second order
    let mut v = [1.0; 6];
    v[1] = f64::INFINITY;
    let e = StopPlan::try_plan_from_state(p, v, [0.0; 6], [2.0; 6], [None; 6]).unwrap_err();
    assert!(matches!(
        e,
        StopError::State {
            axis: 1,
            name: "velocity",
            ..
        }
    ));
}

#[test]
fn overshooting_brake_state_still_ends_at_rest() {
    // Braking at 10 rad/s² with only 1 rad/s left and J = 1: v must cross zero once.
    let stop = StopPlan::plan_from_state([0.0; 6], [1.0; 6], [-10.0; 6], [20.0; 6], [Some(1.0); 6]);
    let end = stop.sample(stop.duration());
    assert_eq!((end.velocity, end.acceleration), ([0.0; 6], [0.0; 6]));
    let just_before = stop.sample(stop.duration() * (1.0 - 1e-9));
    assert!(just_before.velocity[0].abs() < 1e-6 && just_before.acceleration[0].abs() < 1e-6);
}

fn state() -> impl Strategy<Value = (f64, f64, f64, f64, Option<f64>)> {
    (
        -3.0..3.0f64,
        -5.0..5.0f64,
        0.05..50.0f64,
        prop_oneof![Just(None), (0.5..2000.0f64).prop_map(Some)],
    )
        .prop_flat_map(|(p, v, d, j)| (Just(p), Just(v), -2.0 * d..2.0 * d, Just(d), Just(j)))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn stop_from_cruise_stays_within_the_predicted_distance(
        axes in proptest::array::uniform6((-3.0..3.0f64, -5.0..5.0f64, 0.05..50.0f64,
            prop_oneof![Just(None), (0.5..2000.0f64).prop_map(Some)])),
    ) {
        let (p, v, d, j) = (axes.map(|x| x.0), axes.map(|x| x.1), axes.map(|x| x.2), axes.map(|x| x.3));
        let stop = StopPlan::plan_from_state(p, v, [0.0; 6], d, j);
        let n = 1000;
        let mut prev = stop.sample(0.0);
        for k in 1..=n {
            let s = stop.sample(stop.duration() * k as f64 / n as f64);
            for i in 0..6 {
                let bound = stopping_distance(v[i], d[i], j[i]);
                let moved = (s.position[i] - p[i]) * v[i].signum();
                prop_assert!(moved >= -1e-12 && moved <= bound * (1.0 + 1e-9) + 1e-12, "axis {i}: {moved} vs {bound}");
                // Speed only decreases, never reverses.
                prop_assert!(s.velocity[i].abs() <= prev.velocity[i].abs() + 1e-12);
                prop_assert!(s.velocity[i] * v[i] >= -1e-12);
                prop_assert!(s.acceleration[i].abs() <= d[i] * (1.0 + 1e-9));
            }
            prev = s;
        }
        let end = stop.sample(stop.duration());
        prop_assert_eq!(end.velocity, [0.0; 6]);
        prop_assert_eq!(end.acceleration, [0.0; 6]);
        for i in 0..6 {
            let bound = stopping_distance(v[i], d[i], j[i]);
            prop_assert!((stop.distances()[i].abs() - bound).abs() <= 1e-9 * bound.max(1e-3));
            prop_assert_eq!(end.position[i], stop.end_positions()[i]);
        }
    }

    #[test]
    fn stop_from_any_state_ends_at_rest_within_limits((p, v, a, d, j) in state()) {
        let stop = StopPlan::plan_from_state([p; 6], [v; 6], [a; 6], [d; 6], [j; 6]);
        let t_end = stop.duration();
        let n = 1000;
        let a_bound = if j.is_some() { d.max(a.abs()) } else { d };
        let mut prev = (0.0, stop.sample(0.0));
        prop_assert_eq!(prev.1.position[0], p);
        for k in 1..=n {
            let t = t_end * k as f64 / n as f64;
            let s = stop.sample(t);
            prop_assert!(s.acceleration[0].abs() <= a_bound * (1.0 + 1e-9) + 1e-12);
            if let Some(j) = j {
                let da = (s.acceleration[0] - prev.1.acceleration[0]).abs();
                prop_assert!(da <= j * (t - prev.0) * (1.0 + 1e-6) + 1e-9 * d, "jerk {}", da / (t - prev.0));
                // Continuity: position and velocity change no faster than v and a allow.
                let dv = (s.velocity[0] - prev.1.velocity[0]).abs();
                prop_assert!(dv <= d.max(a.abs()) * (t - prev.0) * (1.0 + 1e-6) + 1e-9);
            }
            prev = (t, s);
        }
        let end = stop.sample(t_end);
        prop_assert_eq!((end.velocity[0], end.acceleration[0]), (0.0, 0.0));
        // The last sample before the end is already (almost) at rest: no jump at the end.
        let before = stop.sample(t_end * (1.0 - 1e-12));
        prop_assert!(before.velocity[0].abs() <= 1e-6 * v.abs().max(1.0));
        prop_assert!((before.position[0] - end.position[0]).abs() <= 1e-9);
        prop_assert!((stopping_distance_from(v, a, d, j) - (end.position[0] - p)).abs() <= 1e-12 * (1.0 + (end.position[0] - p).abs()));
    }
}
