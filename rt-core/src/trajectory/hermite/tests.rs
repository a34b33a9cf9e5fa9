use super::*;
use proptest::prelude::*;

const LIM: AxisLimits = AxisLimits {
    velocity: 20.0,
    acceleration: 1e4,
    jerk: None,
};

#[test]
fn interior_overshoot_is_caught_although_the_knots_are_inside() {
    // v(τ) = 12 − 4200τ + 3e5τ² has a root at τ = 4 ms, where p = 1.0008 > 1.
    let seg = Hermite::new(0.98, 12.0, 0.99, 0.0, 0.01);
    match seg.check(-1.0, 1.0, LIM) {
        Err(SegmentError::Position {
            position, tau, max, ..
        }) => {
            assert!((tau - 0.004).abs() < 1e-12, "{tau}");
            assert!(
                (position - 1.0008).abs() < 1e-12 && max == 1.0,
                "{position}"
            );
        }
        other => panic!("expected a position error, got {other:?}"),
    }
    assert_eq!(seg.check(-1.0, 1.01, LIM), Ok(()));
    let msg = seg.check(-1.0, 1.0, LIM).unwrap_err().to_string();
    assert!(msg.contains("1.0008") && msg.contains("[-1, 1]"), "{msg}");
}

#[test]
fn interior_velocity_peak_and_end_accelerations_are_checked() {
    // Rest to rest over 0.1 rad in 0.1 s: v peaks at 1.5 rad/s in the middle, a(0) = 60.
    let seg = Hermite::new(0.0, 0.0, 0.1, 0.0, 0.1);
    let slow = AxisLimits {
        velocity: 1.2,
        acceleration: 100.0,
        jerk: None,
    };
    match seg.check(-1.0, 1.0, slow) {
        Err(SegmentError::Velocity {
            velocity,
            tau,
            limit,
        }) => {
            assert!((velocity - 1.5).abs() < 1e-12 && (tau - 0.05).abs() < 1e-12 && limit == 1.2);
        }
        other => panic!("expected a velocity error, got {other:?}"),
    }
    let weak = AxisLimits {
        velocity: 2.0,
        acceleration: 59.0,
        jerk: None,
    };
    assert!(
        matches!(seg.check(-1.0, 1.0, weak), Err(SegmentError::Acceleration { tau, .. }) if tau == 0.0)
    );
    let fine = AxisLimits {
        velocity: 1.5,
        acceleration: 60.0,
        jerk: None,
    };
    assert_eq!(seg.check(-1.0, 1.0, fine), Ok(()));
    assert!((seg.jerk() + 6.0 * 0.2 / 1e-3).abs() < 1e-9);
}

#[test]
fn invalid_segments_are_typed_errors() {
    assert!(matches!(
        Hermite::try_new(0.0, 0.0, 1.0, 0.0, 0.0),
        Err(SegmentError::Duration { .. })
    ));
    assert!(matches!(
        Hermite::try_new(0.0, f64::NAN, 1.0, 0.0, 0.01),
        Err(SegmentError::NonFinite {
            name: "start velocity",
            ..
        })
    ));
    let h = Hermite::new(0.0, 0.0, 1.0, 0.0, -1.0);
    assert_eq!(h.sample(0.5), (0.0, 0.0, 0.0));
    assert!(h.check(-1.0, 1.0, LIM).is_err());
    let ok = Hermite::new(0.0, 0.0, 0.0, 0.0, 0.01);
    assert!(matches!(
        ok.check(1.0, 1.0, LIM),
        Err(SegmentError::Range { .. })
    ));
    let zero = AxisLimits {
        velocity: 0.0,
        ..LIM
    };
    assert!(matches!(
        ok.check(-1.0, 1.0, zero),
        Err(SegmentError::Limit {
            name: "velocity",
            ..
        })
    ));
}

#[test]
fn six_axis_segment_names_the_failing_axis() {
    let from = PvtPoint::default();
    let mut to = PvtPoint::default();
    to.position[4] = 0.1;
    let seg = PvtSegment::new(&from, &to, 0.1);
    let slow = [AxisLimits {
        velocity: 1.2,
        acceleration: 100.0,
        jerk: None,
    }; 6];
    let err = seg.check(&[-1.0; 6], &[1.0; 6], &slow).unwrap_err();
    assert_eq!(err.axis, 4);
    assert!(err.to_string().starts_with("axis index 4"));
    assert_eq!(seg.sample(0.1).position, to.position);
}

fn knot() -> impl Strategy<Value = (f64, f64)> {
    (-1.2..1.2f64, -3.0..3.0f64)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    #[test]
    fn passes_through_knots_with_continuous_velocity(
        knots in proptest::collection::vec(knot(), 2..12),
        dt in 0.002..0.05f64,
    ) {
        let segs: Vec<Hermite> = knots.windows(2)
            .map(|w| Hermite::new(w[0].0, w[0].1, w[1].0, w[1].1, dt)).collect();
        for (k, s) in segs.iter().enumerate() {
            let (p0, v0, _) = s.sample(0.0);
            let (p1, v1, _) = s.sample(dt);
            prop_assert_eq!((p0, v0), knots[k]);
            prop_assert_eq!((p1, v1), knots[k + 1]);
            // The polynomial itself (not only the clamped ends) meets the knots.
            let (pe, ve) = (s.position_at(dt), s.velocity_at(dt));
            prop_assert!((pe - p1).abs() < 1e-9 && (ve - v1).abs() < 1e-6);
            // Matches the Hermite-basis form.
            let tau = 0.37 * dt;
            let x = tau / dt;
            let basis = (2.0*x*x*x - 3.0*x*x + 1.0) * p0 + (x*x*x - 2.0*x*x + x) * dt * v0
                + (-2.0*x*x*x + 3.0*x*x) * p1 + (x*x*x - x*x) * dt * v1;
            prop_assert!((s.sample(tau).0 - basis).abs() < 1e-12);
        }
        for w in segs.windows(2) {
            let (pa, va, _) = w[0].sample(dt);
            let (pb, vb, _) = w[1].sample(0.0);
            prop_assert_eq!((pa, va), (pb, vb));
            // Approaching the knot from inside the first segment also meets it.
            let (pi, vi, _) = w[0].sample(dt * (1.0 - 1e-9));
            prop_assert!((pi - pb).abs() < 1e-8 && (vi - vb).abs() < 1e-5);
        }
    }

    #[test]
    fn check_agrees_with_dense_sampling(
        (p0, v0) in knot(), (p1, v1) in knot(), dt in 0.005..0.2f64, a_max in 10.0..2000.0f64,
    ) {
        let (min, max) = (-1.0, 1.0);
        let lim = AxisLimits { velocity: 2.0, acceleration: a_max, jerk: None };
        let seg = Hermite::new(p0, v0, p1, v1, dt);
        let verdict = seg.check(min, max, lim);
        // Worst excess over the limits found on a dense grid, relative to each limit.
        let mut excess: f64 = 0.0;
        let n = 4000;
        for k in 0..=n {
            let (p, v, a) = seg.sample(dt * k as f64 / n as f64);
            excess = excess.max(p - max).max(min - p);
            excess = excess.max(v.abs() / lim.velocity - 1.0).max(a.abs() / lim.acceleration - 1.0);
        }
        if verdict.is_ok() {
            prop_assert!(excess <= 1e-8, "check passed but the grid exceeds a limit by {excess}");
        }
        if excess > 1e-6 {
            prop_assert!(verdict.is_err(), "grid exceeds a limit by {excess} but check passed");
        }
    }
}
