use super::*;
use mcm_shared::config::RobotConfig;
use proptest::prelude::*;

const EPS: f64 = 1e-9;

fn params() -> SafetyParams {
    SafetyParams::from_config(&RobotConfig::prob2_default())
}

/// The velocity check's trip velocities [rad/s].
fn v_trip() -> [f64; 6] {
    crate::safety::VelocityLimits::from_config(&RobotConfig::prob2_default()).trip
}

fn one(axis: usize, x: f64) -> [f64; 6] {
    let mut a = [0.0; 6];
    a[axis] = x;
    a
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

#[test]
fn worked_numbers_of_section_5_6() {
    // Second order d2 = v^2 / (2a), in degrees.
    assert!(close(braking_distance(90.0, 180.0, 0.0), 22.5));
    assert!(close(braking_distance(30.0, 180.0, 0.0), 2.5));
    assert!(close(braking_distance(150.0, 360.0, 0.0), 31.25));
    // + latency 10 ms: 0.9, 0.3, 1.5 deg; direction does not matter.
    assert!(close(braking_distance(-90.0, 180.0, 0.01), 22.5 + 0.9));
    assert!(close(braking_distance(30.0, 180.0, 0.01), 2.5 + 0.3));
    assert!(close(braking_distance(150.0, 360.0, 0.01), 31.25 + 1.5));
    // Jerk-limited (trapezoidal) d3 = d2 + v a / (2 j): latency + a / (2 j).
    assert!(close(braking_distance(90.0, 180.0, 180.0 / 3600.0), 27.0));
    assert!(close(braking_distance(30.0, 180.0, 180.0 / 3600.0), 4.0));
    assert!(close(braking_distance(150.0, 360.0, 360.0 / 7200.0), 38.75));
    assert_eq!(braking_distance(0.0, 180.0, 0.01), 0.0);
}

#[test]
fn bad_braking_inputs_are_never_small() {
    assert_eq!(braking_distance(1.0, 0.0, 0.01), f64::INFINITY);
    assert_eq!(braking_distance(1.0, f64::NAN, 0.01), f64::INFINITY);
    assert!(braking_distance(f64::NAN, 1.0, 0.01).is_nan());
    assert!(braking_distance(1.0, 1.0, f64::NAN).is_nan());
    assert_eq!(braking_distance(2.0, 1.0, -5.0), 2.0);
}

/// The trigger distances of the 5.6 table (Ts = 10 ms, 2-cycle latency, m = 1 deg,
/// jerk-limited stop, a_b = a_max) come out of `SafetyParams` + `check_braking`.
#[test]
fn trigger_distance_table_of_section_5_6() {
    let mut cfg = RobotConfig::prob2_default();
    cfg.cycle.rate_hz = 100;
    cfg.safety.braking_efficiency = 1.0;
    cfg.axes[3].max_acceleration_deg_s2 = 360.0;
    cfg.axes[3].max_jerk_deg_s3 = Some(3600.0);
    let p = SafetyParams::from_config(&cfg).with_jerk_limited_stop(&cfg);
    for (axis, v_deg, expected) in [(0, 90.0, 30.7), (0, 30.0, 5.9), (3, 150.0, 44.25)] {
        let v = f64::to_radians(v_deg);
        // Distance before the limit at which the check trips: look-ahead + d(v) + margin.
        let distance = predicted_stop(&p, axis, 0.0, v) + p.margin;
        assert!(
            (distance.to_degrees() - expected).abs() < 1e-9,
            "{v_deg}: {}",
            distance.to_degrees()
        );
    }
    // The shipped P-Rob2 (200 Hz, second order, a_b = 0.8 * 180 deg/s^2) at 90 deg/s:
    // 0.45 look-ahead + 0.9 latency + 28.125 braking + 1 margin = 30.475 deg.
    let p = params();
    let distance = predicted_stop(&p, 0, 0.0, 90f64.to_radians()) + p.margin;
    assert!((distance.to_degrees() - 30.475).abs() < 1e-9);
}

#[test]
fn just_inside_and_outside_the_trigger_on_each_axis_both_directions() {
    let p = params();
    for i in 0..6 {
        for frac in [0.3, 1.0, 1.1] {
            let v = frac * p.v_max[i];
            let d = braking_distance(v, p.brake_decel[i], p.braking_latency_s(i));
            // Toward q_max.
            let hi = p.q_max[i] - p.margin;
            let q_trig = hi - v * p.cycle_s - d;
            assert_eq!(check_braking(&p, &one(i, q_trig - EPS), &one(i, v)), Ok(()));
            let e = check_braking(&p, &one(i, q_trig + EPS), &one(i, v)).unwrap_err();
            assert_eq!((e.check, e.axis, e.limit), (Check::BrakingDistance, i, hi));
            assert!(
                (e.value - (hi + EPS)).abs() < 1e-12,
                "value is the predicted stop"
            );
            // Toward q_min.
            let lo = p.q_min[i] + p.margin;
            let q_trig = lo + v * p.cycle_s + d;
            assert_eq!(
                check_braking(&p, &one(i, q_trig + EPS), &one(i, -v)),
                Ok(())
            );
            let e = check_braking(&p, &one(i, q_trig - EPS), &one(i, -v)).unwrap_err();
            assert_eq!((e.check, e.axis, e.limit), (Check::BrakingDistance, i, lo));
            assert!((e.value - (lo - EPS)).abs() < 1e-12);
        }
    }
}

#[test]
fn at_rest_never_trips_even_in_the_margin_band() {
    let p = params();
    for i in 0..6 {
        assert_eq!(
            check_braking(&p, &one(i, p.q_max[i] - p.margin / 2.0), &[0.0; 6]),
            Ok(())
        );
        assert_eq!(check_braking(&p, &one(i, p.q_min[i]), &[0.0; 6]), Ok(()));
    }
}

#[test]
fn non_finite_inputs_trip() {
    let p = params();
    for i in 0..6 {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for v in [0.0, 0.1, -0.1] {
                let e = check_braking(&p, &one(i, bad), &one(i, v)).unwrap_err();
                assert_eq!(
                    (e.check, e.axis),
                    (Check::BrakingDistance, i),
                    "q={bad} v={v}"
                );
            }
            let e = check_braking(&p, &[0.0; 6], &one(i, bad)).unwrap_err();
            assert_eq!((e.check, e.axis), (Check::BrakingDistance, i), "v={bad}");
            assert_eq!(velocity_cap(&p, i, bad, 1.0), 0.0);
        }
        assert_eq!(velocity_cap(&p, i, 0.0, f64::NAN), 0.0);
    }
    assert_eq!(velocity_cap(&p, 6, 0.0, 1.0), 0.0);
    assert!(predicted_stop(&p, 6, 0.0, 1.0).is_nan());
}

#[test]
fn velocity_cap_shape() {
    let p = params();
    for i in 0..6 {
        // Far from both limits the nominal maximum applies.
        assert_eq!(velocity_cap(&p, i, 0.0, 1.0), p.v_max[i]);
        assert_eq!(velocity_cap(&p, i, 0.0, 0.0), p.v_max[i]);
        // Inside the margin band: no motion toward the limit, full speed away from it.
        let q = p.q_max[i] - p.margin / 2.0;
        assert_eq!(velocity_cap(&p, i, q, 1.0), 0.0);
        assert_eq!(velocity_cap(&p, i, q, 0.0), 0.0);
        assert_eq!(velocity_cap(&p, i, q, -1.0), p.v_max[i]);
        // Monotone: closer to the limit, lower cap.
        let a = velocity_cap(&p, i, p.q_max[i] - 0.05, 1.0);
        let b = velocity_cap(&p, i, p.q_max[i] - 0.10, 1.0);
        assert!(0.0 < a && a < b && b < p.v_max[i], "{a} {b}");
    }
}

/// Simulate all axes at constant velocity from a state the check accepts until the check
/// trips, then (every axis) keep the speed for the latency and brake at a_b to a standstill.
fn simulate_stop(p: &SafetyParams, q0: [f64; 6], v: [f64; 6]) -> Result<[f64; 6], TestCaseError> {
    let mut q = q0;
    let mut steps = 0u32;
    while check_braking(p, &q, &v).is_ok() {
        for (x, w) in q.iter_mut().zip(v) {
            *x += w * p.cycle_s;
        }
        steps += 1;
        prop_assert!(steps < 200_000, "never tripped: q={q:?} v={v:?}");
    }
    // Every axis stops (`docs/safety.md`, "Braking distance"): constant speed for the latency, then
    // braking at a_b, integrated in small steps.
    let mut stop = q;
    for (i, stop) in stop.iter_mut().enumerate() {
        let (a, s) = (p.brake_decel[i], v[i].signum());
        let mut x = q[i] + v[i] * p.braking_latency_s(i);
        let mut w = v[i].abs();
        let dt = 1e-4;
        while w > 0.0 {
            let step = if w <= a * dt {
                w * w / (2.0 * a)
            } else {
                w * dt - 0.5 * a * dt * dt
            };
            x += s * step;
            w -= a * dt;
        }
        *stop = x;
    }
    Ok(stop)
}

fn start_state() -> impl Strategy<Value = ([f64; 6], [f64; 6])> {
    let p = params();
    let v_trip = v_trip();
    prop::array::uniform6((0.0f64..=1.0, 0.05f64..=1.0, any::<bool>())).prop_map(move |axes| {
        let mut q = [0.0; 6];
        let mut v = [0.0; 6];
        for (i, (f, vf, neg)) in axes.into_iter().enumerate() {
            q[i] = p.q_min[i] + f * (p.q_max[i] - p.q_min[i]);
            v[i] = if neg { -vf } else { vf } * v_trip[i];
        }
        (q, v)
    })
}

proptest! {
    #[test]
    fn simulated_stop_ends_before_the_limit((q0, v) in start_state()) {
        let p = params();
        prop_assume!(check_braking(&p, &q0, &v).is_ok());
        let stop = simulate_stop(&p, q0, v)?;
        for (i, &x) in stop.iter().enumerate() {
            let (lo, hi) = (p.q_min[i], p.q_max[i]);
            // Before the margin line of the limit it moves towards (tiny tolerance for the
            // integration's rounding); an axis that started inside the margin band moving
            // away from that limit may end there too ...
            if v[i] > 0.0 {
                prop_assert!(x <= hi - p.margin + 1e-9, "axis {i}: stop {x} > {hi} - margin");
            } else {
                prop_assert!(x >= lo + p.margin - 1e-9, "axis {i}: stop {x} < {lo} + margin");
            }
            // ... and strictly before either limit.
            prop_assert!(x < hi && x > lo, "axis {i}: stop {x} at or past a limit");
        }
    }

    #[test]
    fn moving_away_from_a_limit_never_trips(
        axis in 0usize..6, offset_deg in -10.0f64..5.0, vf in 0.0f64..=1.0, upper in any::<bool>()
    ) {
        let p = params();
        let v_trip = v_trip();
        let off = offset_deg.to_radians();
        // From 10 deg inside up to 5 deg beyond the limit, moving back at up to v_trip.
        let (q, v) = if upper {
            (p.q_max[axis] + off, -vf * v_trip[axis])
        } else {
            (p.q_min[axis] - off, vf * v_trip[axis])
        };
        prop_assert_eq!(check_braking(&p, &one(axis, q), &one(axis, v)), Ok(()));
    }

    #[test]
    fn moving_at_the_cap_never_trips_and_faster_does(
        axis in 0usize..6, f in 0.0f64..=1.0, up in any::<bool>()
    ) {
        let p = params();
        let q = p.q_min[axis] + f * (p.q_max[axis] - p.q_min[axis]);
        let dir = if up { 1.0 } else { -1.0 };
        let cap = velocity_cap(&p, axis, q, dir);
        prop_assert!((0.0..=p.v_max[axis]).contains(&cap));
        prop_assert_eq!(check_braking(&p, &one(axis, q), &one(axis, dir * cap)), Ok(()));
        if cap > 1e-3 && cap < 0.999 * p.v_max[axis] {
            let faster = dir * cap * 1.001;
            prop_assert!(check_braking(&p, &one(axis, q), &one(axis, faster)).is_err());
        }
    }
}

#[test]
fn an_accelerating_axis_is_judged_where_it_stops_after_accelerating_for_the_latency() {
    let p = params();
    let (axis, hi) = (5, p.q_max[5] - p.margin);
    let t = p.cycle_s + p.braking_latency_s(axis);
    let a_b = p.brake_decel[axis];
    // At rest 0.5 deg before the line: no acceleration, no trip; pushed outwards hard, a trip
    // naming the stop it predicts; pushed inwards, none.
    let q = one(axis, hi - 0.5f64.to_radians());
    let zero = [0.0; 6];
    assert!(check_braking_accelerating(&p, &q, &zero, &zero).is_ok());
    let a = 200.0;
    let e = check_braking_accelerating(&p, &q, &zero, &one(axis, a)).unwrap_err();
    let v1 = a * t;
    let stop = q[axis] + 0.5 * a * t * t + v1 * v1 / (2.0 * a_b);
    assert_eq!((e.check, e.axis), (Check::BrakingDistance, axis));
    assert!(close(e.value, stop) && close(e.limit, hi), "{e:?}");
    assert!(check_braking_accelerating(&p, &q, &zero, &one(axis, -a)).is_ok());
    // The lower limit, mirrored.
    let lo = p.q_min[axis] + p.margin;
    let q = one(axis, lo + 0.5f64.to_radians());
    let e = check_braking_accelerating(&p, &q, &zero, &one(axis, -a)).unwrap_err();
    assert!(close(e.limit, lo), "{e:?}");
    // Not finite: a trip.
    assert!(check_braking_accelerating(&p, &zero, &zero, &one(axis, f64::NAN)).is_err());
}

proptest! {
    /// Without acceleration it is the braking check; with one towards the limit it trips
    /// whenever the braking check does (it never judges an axis pushed outwards more kindly).
    #[test]
    fn it_is_the_braking_check_without_acceleration_and_never_kinder_with_one(
        axis in 0usize..6,
        frac in -1.2f64..1.2,
        v in -3.0f64..3.0,
        a in 0.0f64..500.0,
    ) {
        let p = params();
        let mid = 0.5 * (p.q_max[axis] + p.q_min[axis]);
        let half = 0.5 * (p.q_max[axis] - p.q_min[axis]);
        let q = one(axis, mid + frac * half);
        let qd = one(axis, v);
        let plain = check_braking(&p, &q, &qd).is_err();
        prop_assert_eq!(check_braking_accelerating(&p, &q, &qd, &[0.0; 6]).is_err(), plain);
        let outwards = one(axis, a * v.signum());
        if plain {
            prop_assert!(check_braking_accelerating(&p, &q, &qd, &outwards).is_err());
        }
    }
}
