use super::*;
use proptest::prelude::*;

const DEG: f64 = std::f64::consts::PI / 180.0;

fn lim(v: f64, a: f64, j: Option<f64>) -> AxisLimits {
    AxisLimits {
        velocity: v * DEG,
        acceleration: a * DEG,
        jerk: j.map(|j| j * DEG),
    }
}

#[test]
fn reference_move_all() {
    let l = [lim(90.0, 180.0, Some(1800.0)); 6];
    let target = [90.0 * DEG, -30.0 * DEG, 0.0, 45.0 * DEG, 0.0, 10.0 * DEG];
    let p = MovePlan::plan([0.0; 6], target, &l, 1.0).unwrap();
    assert!((p.duration() - 1.6).abs() < 1e-9);
    assert_eq!(p.longest_axis(), 0);
    let v = p.velocities();
    assert!((v[0] - 90.0 * DEG).abs() < 1e-12 && (v[1] - 30.0 * DEG).abs() < 1e-12);
    assert_eq!(v[2], 0.0);
    let mid = p.sample(0.8);
    assert!((mid.velocity[3] - 45.0 * DEG).abs() < 1e-9);
    assert_eq!(p.sample(1.6).position, target);
    // f = 0.5 scales V, A (and J) by 0.5; trapezoid: T = D/(fV) + V/A = 2 + 0.5.
    let l = [lim(90.0, 180.0, None); 6];
    let p = MovePlan::plan([0.0; 6], target, &l, 0.5).unwrap();
    assert!((p.duration() - 2.5).abs() < 1e-9);
    assert!((p.velocities()[0] - 45.0 * DEG).abs() < 1e-12);
}

#[test]
fn longest_axis_is_the_slowest_on_its_own() {
    let mut l = [lim(90.0, 180.0, None); 6];
    l[4] = lim(30.0, 60.0, None);
    let target = [1.0, 0.5, 0.0, 0.0, 0.6, 0.0];
    let p = MovePlan::plan([0.0; 6], target, &l, 1.0).unwrap();
    assert_eq!(p.longest_axis(), 4);
    let own = Profile1D::plan(0.6, l[4]).unwrap().duration();
    assert!((p.axis_durations()[4] - own).abs() < 1e-15);
    assert!(p.duration() >= own * (1.0 - 1e-12));
    assert!((p.velocities()[4] - l[4].velocity).abs() < 1e-12 || p.duration() > own);
}

#[test]
fn move_axis_is_a_single_axis_profile() {
    let l = [lim(150.0, 360.0, Some(3600.0)); 6];
    let start = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6];
    let p = MovePlan::plan_axis(start, 5, 0.6 - 180.0 * DEG, &l, 1.0).unwrap();
    assert!((p.duration() - 1.7167).abs() < 6e-5);
    assert_eq!(p.longest_axis(), 5);
    let s = p.sample(0.5);
    assert_eq!(s.position[..5], start[..5]);
    assert!(matches!(
        MovePlan::plan_axis(start, 6, 0.0, &l, 1.0),
        Err(PlanError::AxisIndex { axis: 6 })
    ));
    let none = MovePlan::plan(start, start, &l, 1.0).unwrap();
    assert_eq!((none.duration(), none.sample(0.0).position), (0.0, start));
}

#[test]
fn bad_inputs_are_typed_errors() {
    let l = [lim(90.0, 180.0, None); 6];
    for f in [0.0, -0.1, 1.0001, f64::NAN] {
        let e = MovePlan::plan([0.0; 6], [1.0; 6], &l, f).unwrap_err();
        assert!(matches!(e, PlanError::VelocityFactor { .. }));
        assert!(e.to_string().contains("(0, 1]"));
    }
    let mut t = [0.0; 6];
    t[3] = f64::INFINITY;
    assert!(matches!(
        MovePlan::plan([0.0; 6], t, &l, 1.0),
        Err(PlanError::Target { axis: 3, .. })
    ));
    assert!(matches!(
        MovePlan::plan(t, [0.0; 6], &l, 1.0),
        Err(PlanError::Start { axis: 3, .. })
    ));
    let big = [1e308, 0.0, 0.0, 0.0, 0.0, 0.0];
    assert!(matches!(
        MovePlan::plan(big.map(|x| -x), big, &l, 1.0),
        Err(PlanError::Delta { axis: 0, .. })
    ));
    let mut bad = l;
    bad[2].acceleration = 0.0;
    let e = MovePlan::plan([0.0; 6], [1.0; 6], &bad, 1.0).unwrap_err();
    assert!(
        matches!(
            e,
            PlanError::AxisLimit {
                axis: 2,
                name: "acceleration",
                ..
            }
        ),
        "{e}"
    );
    bad[2] = lim(1.0, 1.0, Some(f64::NAN));
    assert!(matches!(
        MovePlan::plan([0.0; 6], [1.0; 6], &bad, 1.0),
        Err(PlanError::AxisLimit { name: "jerk", .. })
    ));
}

fn axis_strategy() -> impl Strategy<Value = (f64, f64, AxisLimits)> {
    (
        -3.0..3.0f64,
        prop_oneof![Just(0.0), -4.0..-1e-3f64, 1e-3..4.0f64],
        0.05..5.0f64,
        0.05..50.0f64,
        prop_oneof![Just(None), (0.5..2000.0f64).prop_map(Some)],
    )
        .prop_map(|(s, d, v, a, j)| {
            (
                s,
                d,
                AxisLimits {
                    velocity: v,
                    acceleration: a,
                    jerk: j,
                },
            )
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn synchronised_straight_line_within_limits(
        axes in proptest::array::uniform6(axis_strategy()),
        f in prop_oneof![Just(1.0), 0.01..1.0f64],
    ) {
        let start = axes.map(|a| a.0);
        let target = axes.map(|a| a.0 + a.1);
        let limits = axes.map(|a| a.2);
        let p = MovePlan::plan(start, target, &limits, f).unwrap();
        let t_end = p.duration();
        let delta: [f64; 6] = std::array::from_fn(|i| target[i] - start[i]);
        let moving: Vec<usize> = (0..6).filter(|&i| delta[i] != 0.0).collect();

        // Reply fields.
        let own: Vec<f64> = (0..6).map(|i| if delta[i] == 0.0 { 0.0 } else {
            Profile1D::plan(delta[i], limits[i].scaled(f)).unwrap().duration()
        }).collect();
        let max_own = own.iter().cloned().fold(0.0, f64::max);
        prop_assert_eq!(own[p.longest_axis()], max_own);
        prop_assert!(t_end >= max_own * (1.0 - 1e-12));

        let n = 1000;
        let times = (0..=n).map(|k| t_end * k as f64 / n as f64)
            .chain(p.path().phase_times().into_iter().flat_map(|b| [b * (1.0 - 1e-9), b, b * (1.0 + 1e-9)]));
        let mut prev: Option<(f64, JointSample)> = None;
        for t in times {
            let s = p.sample(t);
            let tc = t.clamp(0.0, t_end);
            for i in 0..6 {
                let l = limits[i].scaled(f);
                prop_assert!(s.velocity[i].abs() <= l.velocity * (1.0 + 1e-9) + 1e-12, "axis {i} v");
                prop_assert!(s.acceleration[i].abs() <= l.acceleration * (1.0 + 1e-9) + 1e-12, "axis {i} a");
                prop_assert!(s.velocity[i].abs() <= p.velocities()[i] * (1.0 + 1e-9) + 1e-15);
                if let (Some(j), Some((t0, s0))) = (l.jerk, prev)
                    && tc > t0
                    && p.path().is_jerk_limited()
                {
                    let da = (s.acceleration[i] - s0.acceleration[i]).abs();
                    prop_assert!(da <= j * (tc - t0) * (1.0 + 1e-6) + 1e-9 * l.acceleration.max(1.0), "axis {i} jerk");
                }
            }
            // Straight line: the same fraction of the way on every moving axis.
            if let Some(&first) = moving.first() {
                let frac = (s.position[first] - start[first]) / delta[first];
                for &i in &moving {
                    let fi = (s.position[i] - start[i]) / delta[i];
                    prop_assert!((fi - frac).abs() <= 1e-9, "axis {i} off the line: {fi} vs {frac}");
                }
                if tc < t_end * 0.999 {
                    prop_assert!(frac < 1.0, "arrived early at {tc} of {t_end}");
                }
            }
            prev = Some((tc, s));
        }
        let end = p.sample(t_end);
        prop_assert_eq!(end.position, target);
        prop_assert_eq!(end.velocity, [0.0; 6]);
        prop_assert_eq!(end.acceleration, [0.0; 6]);
        prop_assert_eq!(p.sample(0.0).position, start);
    }
}
