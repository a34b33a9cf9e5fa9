use super::*;
use proptest::prelude::*;

const DEG: f64 = std::f64::consts::PI / 180.0;

fn lim(v: f64, a: f64, j: Option<f64>) -> AxisLimits {
    AxisLimits {
        velocity: v,
        acceleration: a,
        jerk: j,
    }
}

/// The P-Rob2's axis 1.
fn prob2() -> AxisLimits {
    lim(90.0 * DEG, 180.0 * DEG, Some(1800.0 * DEG))
}

/// Checks a plan from (p0, v0, a0) to `target` on a dense grid plus both sides of every
/// switch: the start state, every limit, continuity between samples, the position range and
/// the exact end at rest.
fn check(plan: &AxisPlan, start: (f64, f64, f64), target: f64, l: AxisLimits) {
    let (p0, v0, a0) = start;
    assert_eq!(
        plan.sample(0.0),
        start,
        "starts at the state it was planned from"
    );
    let t_end = plan.duration();
    assert!(t_end.is_finite() && t_end >= 0.0, "duration {t_end}");
    let n = 2000;
    let eps = 1e-9 * t_end.max(1e-9);
    let mut times: Vec<f64> = (0..=n).map(|k| t_end * k as f64 / n as f64).collect();
    for b in plan.switch_times() {
        times.extend([b - eps, b, b + eps]);
    }
    times.retain(|t| *t >= 0.0 && *t <= t_end);
    times.sort_by(f64::total_cmp);
    let (lo, hi) = plan.position_range();
    let tol = |x: f64| x * (1.0 + 1e-9) + 1e-12;
    let (v_lim, a_lim) = (l.velocity.max(v0.abs()), l.acceleration.max(a0.abs()));
    let mut prev = (0.0, start);
    for &t in &times {
        let (p, v, a) = plan.sample(t);
        assert!(v.abs() <= tol(v_lim), "v {v} beyond {v_lim} at {t}");
        assert!(a.abs() <= tol(a_lim), "a {a} beyond {a_lim} at {t}");
        assert!(v.abs() <= tol(plan.peak_velocity()), "peak velocity");
        assert!(
            a.abs() <= tol(plan.peak_acceleration()),
            "peak acceleration"
        );
        assert!(
            p >= lo - 1e-12 && p <= hi + 1e-12,
            "p {p} outside [{lo}, {hi}]"
        );
        let (t0, (p_prev, v_prev, a_prev)) = prev;
        let dt = t - t0;
        // Continuity: no step in position or velocity; in acceleration not beyond the jerk.
        assert!(
            (p - p_prev).abs() <= v_lim * dt * (1.0 + 1e-6) + 1e-10,
            "position jumps at {t}"
        );
        assert!(
            (v - v_prev).abs() <= a_lim * dt * (1.0 + 1e-6) + 1e-9,
            "velocity jumps at {t}: {v_prev} -> {v}"
        );
        if let Some(j) = l.jerk {
            assert!(
                (a - a_prev).abs() <= j * dt * (1.0 + 1e-6) + 1e-8 * a_lim.max(1.0),
                "jerk beyond {j} at {t}: {a_prev} -> {a}"
            );
        }
        prev = (t, (p, v, a));
    }
    assert_eq!(plan.sample(t_end), (target, 0.0, 0.0));
    let (p, v, a) = plan.sample(t_end * (1.0 - 1e-12));
    assert!(
        (p - target).abs() < 1e-9 && v.abs() < 1e-6,
        "no jump at the end"
    );
    assert!(
        l.jerk.is_none() || a.abs() < 1e-4 * a_lim.max(1.0),
        "a {a} just before the end"
    );
    assert!(
        lo <= p0.min(target) + 1e-12 && hi >= p0.max(target) - 1e-12,
        "range covers start and target"
    );
}

#[test]
fn from_rest_it_is_the_standard_profile() {
    for l in [prob2(), lim(1.0, 2.0, None)] {
        let plan = plan_from_state(0, 0.1, 0.0, 0.0, 0.1 + 90.0 * DEG, l, 1.0).unwrap();
        let reference = Profile1D::plan(90.0 * DEG, l).unwrap();
        assert!((plan.duration() - reference.duration()).abs() < 1e-12);
        for k in 0..=100 {
            let t = reference.duration() * k as f64 / 100.0;
            let (p, v, a) = plan.sample(t);
            let (rp, rv, ra) = reference.sample(t);
            assert!((p - 0.1 - rp).abs() < 1e-12 && (v - rv).abs() < 1e-12);
            assert!((a - ra).abs() < 1e-9 || l.jerk.is_none());
        }
        check(&plan, (0.1, 0.0, 0.0), 0.1 + 90.0 * DEG, l);
    }
}

#[test]
fn retarget_ahead_keeps_going_and_behind_turns_back() {
    let l = prob2();
    // Cruising at 45 deg/s toward +; a target far ahead: no stop on the way.
    let ahead = plan_from_state(0, 0.0, 45.0 * DEG, 0.0, 1.0, l, 0.5).unwrap();
    check(&ahead, (0.0, 45.0 * DEG, 0.0), 1.0, l);
    let mut min_speed = f64::INFINITY;
    for k in 0..100 {
        let t = ahead.duration() * 0.5 * k as f64 / 100.0;
        min_speed = min_speed.min(ahead.sample(t).1);
    }
    assert!(min_speed > 40.0 * DEG, "never slows down much: {min_speed}");
    // A target behind: overshoots by the braking distance (full limits: d3 = 4 deg from
    // 30 deg/s, `controlled_stop`'s module doc), then comes back.
    let back = plan_from_state(0, 0.0, 30.0 * DEG, 0.0, -0.2, l, 1.0).unwrap();
    check(&back, (0.0, 30.0 * DEG, 0.0), -0.2, l);
    assert!((back.position_range().1 - 4.0 * DEG).abs() < 1e-9);
    // Faster than the new factor allows: slows down at once, then within the new limits.
    let slow = plan_from_state(0, 0.0, 90.0 * DEG, 0.0, 2.0, l, 0.2).unwrap();
    check(&slow, (0.0, 90.0 * DEG, 0.0), 2.0, l);
    assert!(slow.sample(0.5).1 <= 18.0 * DEG + 1e-12);
}

#[test]
fn bad_inputs_are_typed_errors() {
    let l = prob2();
    assert!(matches!(
        plan_from_state(2, f64::NAN, 0.0, 0.0, 1.0, l, 1.0),
        Err(PlanError::Start { axis: 2, .. })
    ));
    assert!(matches!(
        plan_from_state(1, 0.0, 0.0, 0.0, f64::INFINITY, l, 1.0),
        Err(PlanError::Target { axis: 1, .. })
    ));
    assert!(matches!(
        plan_from_state(0, 0.0, 0.0, 0.0, 1.0, l, 0.0),
        Err(PlanError::VelocityFactor { .. })
    ));
    assert!(matches!(
        plan_from_state(0, 0.0, 0.0, 0.0, 1.0, lim(1.0, -1.0, None), 1.0),
        Err(PlanError::Limit { .. })
    ));
}

#[test]
fn joint_plan_axes_are_independent_and_from_move_is_the_straight_line() {
    let l = [prob2(); 6];
    let target = [0.5, -0.2, 0.0, 0.3, 0.1, -0.4];
    let mv = MovePlan::plan([0.0; 6], target, &l, 0.7).unwrap();
    let mut joint = JointPlan::from_move(&mv).unwrap();
    assert!((joint.remaining() - mv.duration()).abs() < 1e-12);
    let dt = 0.005;
    let mut t = 0.0;
    for _ in 0..40 {
        t += dt;
        let s = joint.advance(dt);
        let r = mv.sample(t);
        for i in 0..6 {
            assert!((s.position[i] - r.position[i]).abs() < 1e-12);
            assert!((s.velocity[i] - r.velocity[i]).abs() < 1e-12);
        }
    }
    // Re-target axis 2 only: axis 1 keeps its plan.
    let before = joint.sample();
    let new2 = plan_from_state(
        1,
        before.position[1],
        before.velocity[1],
        before.acceleration[1],
        0.4,
        l[1],
        0.7,
    )
    .unwrap();
    joint.set_axis(1, new2);
    assert_eq!(joint.sample(), before, "no step at the switch");
    while !joint.finished() {
        t += dt;
        let s = joint.advance(dt);
        let r = mv.sample(t);
        assert!(
            (s.position[0] - r.position[0]).abs() < 1e-12,
            "axis 1 untouched"
        );
    }
    let end = joint.sample();
    assert_eq!(end.position[0], target[0]);
    assert_eq!(end.position[1], 0.4);
    assert_eq!((end.velocity, end.acceleration), ([0.0; 6], [0.0; 6]));
    assert_eq!(joint.remaining(), 0.0);
}

/// Limits, a state the limits allow (Ruckig's feasibility: the acceleration can be ramped to
/// zero before the velocity limit), a target and a velocity factor.
fn case() -> impl Strategy<Value = (AxisLimits, (f64, f64, f64), f64, f64)> {
    (
        0.05..5.0f64,
        0.05..50.0f64,
        prop_oneof![Just(None), (0.5..2000.0f64).prop_map(Some)],
        -3.0..3.0f64,
        -1.0..1.0f64,
        -1.0..1.0f64,
        prop_oneof![Just(0.0), -4.0..4.0f64, -1e-3..1e-3f64],
        prop_oneof![Just(1.0), 0.01..1.0f64],
    )
        .prop_map(|(v, a, j, p0, vf, af, d, f)| {
            let l = lim(v, a, j);
            let v0 = vf * v;
            let mut a0 = af * a;
            if let Some(j) = j {
                // |v0 + a0·|a0|/(2J)| <= v_max.
                let room = v - a0.signum() * v0;
                a0 = a0.signum() * a0.abs().min((2.0 * j * room).sqrt());
            }
            (l, (p0, v0, a0), p0 + d, f)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn replans_from_any_allowed_state_are_continuous_bounded_and_arrive(
        (l, start, target, f) in case()
    ) {
        let plan = plan_from_state(0, start.0, start.1, start.2, target, l, f).unwrap();
        check(&plan, start, target, l);
    }

    #[test]
    fn interrupting_a_move_anywhere_and_retargeting_is_seamless(
        (l, _, first, f) in case(),
        second in -4.0..4.0f64,
        g in prop_oneof![Just(1.0), 0.01..1.0f64],
        at in 0.0..1.0f64,
    ) {
        let plan = plan_from_state(0, 0.0, 0.0, 0.0, first, l, f).unwrap();
        let t = at * plan.duration();
        let state = plan.sample(t);
        let next = plan_from_state(0, state.0, state.1, state.2, second, l, g).unwrap();
        prop_assert_eq!(next.sample(0.0), state);
        check(&next, state, second, l);
    }
}
