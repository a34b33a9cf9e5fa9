use super::*;
use proptest::prelude::*;

fn lim(v: f64, a: f64, j: Option<f64>) -> AxisLimits {
    AxisLimits {
        velocity: v,
        acceleration: a,
        jerk: j,
    }
}

#[test]
fn durations_match_the_reference_table() {
    // (D, V, A, J, T double-S, T trapezoid), worked out by hand from the closed form of the
    // module doc; units cancel, degrees are fine here.
    let table = [
        (90.0, 90.0, 180.0, 1800.0, 1.600, 1.500),
        (10.0, 90.0, 180.0, 1800.0, 0.5819, 0.4714),
        (1.0, 90.0, 180.0, 1800.0, 0.2610, 0.1491),
        (180.0, 150.0, 360.0, 3600.0, 1.7167, 1.6167),
    ];
    for (d, v, a, j, t_s, t_trap) in table {
        for sign in [1.0, -1.0] {
            let s = Profile1D::plan(sign * d, lim(v, a, Some(j))).unwrap();
            let t = Profile1D::plan(sign * d, lim(v, a, None)).unwrap();
            assert!(
                (s.duration() - t_s).abs() < 6e-5,
                "double-S {d}: {}",
                s.duration()
            );
            assert!(
                (t.duration() - t_trap).abs() < 6e-5,
                "trapezoid {d}: {}",
                t.duration()
            );
        }
    }
}

#[test]
fn ends_exactly_and_clamps_time() {
    let p = Profile1D::plan(-1.234, lim(0.7, 2.0, Some(9.0))).unwrap();
    assert_eq!(p.sample(p.duration()), (-1.234, 0.0, 0.0));
    assert_eq!(p.sample(1e9), (-1.234, 0.0, 0.0));
    assert_eq!(p.sample(-1.0), (0.0, 0.0, 0.0));
    assert_eq!(p.sample(f64::NAN), (0.0, 0.0, 0.0));
    let z = Profile1D::plan(0.0, lim(1.0, 1.0, None)).unwrap();
    assert_eq!((z.duration(), z.sample(0.5)), (0.0, (0.0, 0.0, 0.0)));
}

#[test]
fn bad_inputs_are_typed_errors() {
    let ok = lim(1.0, 1.0, Some(1.0));
    assert!(matches!(
        Profile1D::plan(f64::NAN, ok),
        Err(PlanError::Distance { .. })
    ));
    assert!(matches!(
        Profile1D::plan(f64::INFINITY, ok),
        Err(PlanError::Distance { .. })
    ));
    assert!(matches!(
        Profile1D::plan(1.0, lim(0.0, 1.0, None)),
        Err(PlanError::Limit {
            name: "velocity",
            ..
        })
    ));
    assert!(matches!(
        Profile1D::plan(1.0, lim(1.0, -1.0, None)),
        Err(PlanError::Limit {
            name: "acceleration",
            ..
        })
    ));
    assert!(matches!(
        Profile1D::plan(1.0, lim(1.0, 1.0, Some(f64::INFINITY))),
        Err(PlanError::Limit { name: "jerk", .. })
    ));
    assert!(matches!(
        Profile1D::plan(1e300, lim(1e-300, 1.0, None)),
        Err(PlanError::Duration { .. })
    ));
    let msg = Profile1D::plan(1.0, lim(-2.0, 1.0, None))
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("velocity limit -2") && msg.contains("finite and > 0"),
        "{msg}"
    );
}

/// Grid of 1000 points plus every phase boundary and points just beside it.
fn grid(p: &Profile1D) -> impl Iterator<Item = f64> + '_ {
    let n = 1000;
    let t = p.duration();
    let eps = 1e-9 * t.max(1e-9);
    let uniform = (0..=n).map(move |k| t * k as f64 / n as f64);
    let bounds = p
        .phase_times()
        .into_iter()
        .flat_map(move |b| [b - eps, b, b + eps]);
    uniform.chain(bounds)
}

fn limits_strategy() -> impl Strategy<Value = (f64, AxisLimits)> {
    (
        prop_oneof![1e-6..1e-3f64, 1e-3..20.0f64],
        any::<bool>(),
        1e-2..10.0f64,
        1e-2..100.0f64,
        prop_oneof![Just(None), (1e-2..1e4f64).prop_map(Some)],
    )
        .prop_map(|(d, neg, v, a, j)| (if neg { -d } else { d }, lim(v, a, j)))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn samples_respect_limits_and_end_at_rest((d, l) in limits_strategy()) {
        let p = Profile1D::plan(d, l).unwrap();
        let tol = |x: f64| x * (1.0 + 1e-9) + 1e-12;
        let (lo, hi) = (d.min(0.0), d.max(0.0));
        let mut last = (0.0, 0.0); // (t, a)
        for t in grid(&p) {
            let (pos, v, a) = p.sample(t);
            prop_assert!(v.abs() <= tol(l.velocity), "v {v} > {} at {t}", l.velocity);
            prop_assert!(a.abs() <= tol(l.acceleration), "a {a} > {} at {t}", l.acceleration);
            prop_assert!(pos >= lo && pos <= hi, "p {pos} outside [{lo}, {hi}]");
            prop_assert!(v * d.signum() >= -1e-12, "moves backwards: v {v}");
            if let Some(j) = l.jerk {
                let t_c = t.clamp(0.0, p.duration());
                let (t0, a0) = last;
                if t_c > t0 {
                    let bound = j * (t_c - t0) * (1.0 + 1e-6) + 1e-9 * l.acceleration.max(1.0);
                    prop_assert!((a - a0).abs() <= bound, "jerk over {j} between {t0} and {t_c}");
                }
                last = (t_c, a);
            }
        }
        prop_assert_eq!(p.sample(p.duration()), (d, 0.0, 0.0));
        // Time-optimality: some limit is active.
        let v_active = (p.peak_velocity() - l.velocity).abs() <= 1e-9 * l.velocity;
        let a_active = (p.peak_acceleration() - l.acceleration).abs() <= 1e-9 * l.acceleration;
        prop_assert!(v_active || a_active || p.is_jerk_limited());
    }

    #[test]
    fn position_velocity_acceleration_are_consistent((d, l) in limits_strategy()) {
        // Within one phase v is quadratic and a linear: Simpson and the trapezoid rule are
        // exact there, so p, v, a must agree up to rounding.
        let p = Profile1D::plan(d, l).unwrap();
        let b = p.phase_times();
        let n = 500;
        let h = p.duration() / n as f64;
        for k in 0..n {
            let (t0, t1) = (k as f64 * h, (k + 1) as f64 * h);
            if b.iter().any(|&x| x >= t0 - 1e-12 * h && x <= t1 + 1e-12 * h) {
                continue;
            }
            let (p0, v0, a0) = p.sample(t0);
            let (_, vm, _) = p.sample(t0 + h / 2.0);
            let (p1, v1, a1) = p.sample(t1);
            let tol_p = 1e-9 * (d.abs() + l.velocity * h);
            let tol_v = 1e-9 * (l.velocity + l.acceleration * h);
            prop_assert!((p1 - p0 - h / 6.0 * (v0 + 4.0 * vm + v1)).abs() <= tol_p);
            prop_assert!((v1 - v0 - h / 2.0 * (a0 + a1)).abs() <= tol_v);
        }
    }
}
