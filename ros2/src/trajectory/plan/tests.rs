//! The plan's path: exact at the knots, continuous in velocity, cut into PVT points at `dt`.

use super::super::tests::{DT, T0, at_rest, joints, loose_joints, point, point_pv, traj};
use super::*;
use crate::msgs::trajectory::JointTrajectoryPoint;
use proptest::prelude::*;

const AMPLITUDE: [f64; 6] = [0.3, -0.2, 0.25, 0.4, -0.3, 0.5];
const T_END: f64 = 2.0;

/// Axis i follows A_i·(1 - cos(π t / T))/2: from rest at 0 to rest at A_i.
fn smooth(t: f64) -> ([f64; 6], [f64; 6], [f64; 6]) {
    let w = std::f64::consts::PI / T_END;
    (
        AMPLITUDE.map(|a| a * (1.0 - (w * t).cos()) / 2.0),
        AMPLITUDE.map(|a| a * w * (w * t).sin() / 2.0),
        AMPLITUDE.map(|a| a * w * w * (w * t).cos() / 2.0),
    )
}

/// What MoveIt sends: points every 0.1 s from the start (at t = 0, the start itself), with
/// positions and velocities, and accelerations if `with_acc`.
fn moveit(with_acc: bool) -> JointTrajectory {
    traj(
        (0..=20)
            .map(|k| {
                let t = k as f64 * 0.1;
                let (p, v, a) = smooth(t);
                JointTrajectoryPoint {
                    accelerations: if with_acc {
                        a.to_vec().into()
                    } else {
                        vec![].into()
                    },
                    ..point_pv(t, p, v)
                }
            })
            .collect(),
    )
}

/// |a - b| < tol on every axis.
fn assert_close(a: [f64; 6], b: [f64; 6], tol: [f64; 6], what: &str) {
    for (i, ((a, b), tol)) in a.iter().zip(b).zip(tol).enumerate() {
        assert!((a - b).abs() < tol, "{what}, axis {i}: {a} vs {b}");
    }
}

fn times(t: &JointTrajectory) -> Vec<f64> {
    t.points
        .iter()
        .map(|p| p.time_from_start.as_secs_f64())
        .collect()
}

/// Largest velocity step across the interior knots of `plan` at `knot_times`.
fn largest_velocity_step(plan: &Plan, knot_times: &[f64]) -> f64 {
    let eps = 1e-7;
    knot_times
        .iter()
        .flat_map(|&t| {
            let (before, after) = (plan.sample(t - eps), plan.sample(t + eps));
            (0..6).map(move |i| (after.velocity[i] - before.velocity[i]).abs())
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_moveit_trajectory_is_reproduced_at_its_knots_and_is_c1() {
    let t = moveit(false);
    let plan = Plan::new(&t, &joints(), at_rest([0.0; 6]), T0, DT).unwrap();
    assert_eq!(plan.duration(), T_END);
    for (k, tk) in times(&t).into_iter().enumerate() {
        let s = plan.sample(tk);
        assert_eq!(s.position[..], t.points[k].positions[..], "point {k}");
        assert_eq!(s.velocity[..], t.points[k].velocities[..], "point {k}");
    }
    let inner = &times(&t)[1..20];
    // A step would be of the order of the velocity change over 0.1 s (~0.05 rad/s).
    let step = largest_velocity_step(&plan, inner);
    assert!(step < 1e-5, "velocity steps by {step} rad/s at a knot");
    // And the velocity is the position's derivative, between the knots too.
    for tt in [0.033, 0.55, 1.27, 1.91] {
        let h = 1e-6;
        let (a, b) = (plan.sample(tt - h), plan.sample(tt + h));
        for i in 0..6 {
            let numeric = (b.position[i] - a.position[i]) / (2.0 * h);
            assert!((numeric - plan.sample(tt).velocity[i]).abs() < 1e-6);
        }
    }
    // The cubic follows the smooth path closely between the knots.
    let (p, _, _) = smooth(1.05);
    let s = plan.sample(1.05);
    assert_close(s.position, p, [1e-4; 6], "position at 1.05 s");
}

#[test]
fn accelerations_make_it_quintic_and_continuous_in_acceleration() {
    let t = moveit(true);
    let plan = Plan::new(&t, &joints(), at_rest([0.0; 6]), T0, DT).unwrap();
    let eps = 1e-7;
    for tk in &times(&t)[1..20] {
        let (a, b) = (plan.sample(tk - eps), plan.sample(tk + eps));
        for i in 0..6 {
            assert!(
                (a.acceleration[i] - b.acceleration[i]).abs() < 1e-4,
                "acceleration steps at {tk}, axis {i}"
            );
        }
    }
    // The given acceleration is met at a knot.
    let (_, _, acc) = smooth(0.5);
    let s = plan.sample(0.5);
    assert_close(s.acceleration, acc, [1e-9; 6], "acceleration at 0.5 s");
}

#[test]
fn a_position_only_trajectory_has_a_continuous_velocity() {
    let mut t = moveit(false);
    for p in &mut t.points {
        p.velocities = Default::default();
    }
    let plan = Plan::new(&t, &joints(), at_rest([0.0; 6]), T0, DT).unwrap();
    let step = largest_velocity_step(&plan, &times(&t)[1..20]);
    assert!(step < 1e-5, "velocity steps by {step} rad/s at a knot");
    // The estimates are close to the true velocities, and the end is at rest.
    let (_, v, _) = smooth(1.0);
    let s = plan.sample(1.0);
    assert_close(
        s.velocity,
        v,
        v.map(|v| 0.01 * v.abs() + 1e-9),
        "velocity at 1 s",
    );
    assert_eq!(plan.final_state().velocity, [0.0; 6]);
}

#[test]
fn pvt_points_are_the_samples_every_dt_and_the_last_is_the_final_state() {
    // 1.234 s: not a multiple of dt, so the last point comes after the end.
    let t = traj(vec![
        point(0.0, [0.0; 6]),
        point(0.6, [0.05, 0.0, -0.05, 0.1, 0.0, 0.0]),
        point(1.234, [0.1, 0.05, -0.1, 0.2, 0.05, -0.05]),
    ]);
    let plan = Plan::new(&t, &joints(), at_rest([0.0; 6]), T0, DT).unwrap();
    assert_eq!(plan.point_count(), 124);
    let n = plan.point_count();
    for k in 0..n - 1 {
        let s = plan.sample((k + 1) as f64 * DT);
        let pt = plan.pvt_point(k);
        assert_eq!(
            pt.position_deg,
            s.position.map(f64::to_degrees),
            "point {k}"
        );
        assert_eq!(
            pt.velocity_deg_s,
            s.velocity.map(f64::to_degrees),
            "point {k}"
        );
    }
    let last = plan.pvt_point(n - 1);
    let fin = [0.1, 0.05, -0.1, 0.2, 0.05, -0.05].map(f64::to_degrees);
    assert_eq!(last.position_deg, fin);
    assert_eq!(last.velocity_deg_s, [0.0; 6]);
    assert_eq!(
        plan.pvt_point(n + 5),
        last,
        "beyond the end: the final state"
    );
    // A duration that is a multiple of dt takes exactly duration/dt points.
    let t = traj(vec![point(0.0, [0.0; 6]), point(1.0, [0.1; 6])]);
    let plan = Plan::new(&t, &joints(), at_rest([0.0; 6]), T0, DT).unwrap();
    assert_eq!(plan.point_count(), 100);
}

#[test]
fn joining_a_moving_stream_has_no_velocity_step() {
    let start = StartState {
        position: [0.1, 0.0, 0.0, -0.1, 0.0, 0.0],
        velocity: [0.2, -0.1, 0.05, 0.0, 0.3, -0.2],
    };
    // The new goal starts at the arm's position (time 0, at rest as MoveIt writes it) and
    // goes on from there; the plan starts with the stream's velocity anyway.
    let t = traj(vec![
        point(0.0, start.position),
        point(1.0, [0.3, 0.1, 0.1, -0.1, 0.2, -0.1]),
    ]);
    let plan = Plan::new(&t, &joints(), start, T0, DT).unwrap();
    let s0 = plan.sample(0.0);
    assert_eq!((s0.position, s0.velocity), (start.position, start.velocity));
    let s = plan.sample(1e-7);
    assert_close(
        s.velocity,
        start.velocity,
        [1e-5; 6],
        "velocity just after 0",
    );
    // The first PVT point continues the motion: about start + v·dt.
    let p = plan.pvt_point(0).position_deg;
    let expect = std::array::from_fn(|i| start.position[i] + start.velocity[i] * DT);
    assert_close(p.map(f64::to_radians), expect, [1e-3; 6], "first PVT point");
    // Before the start the plan is the start state.
    assert_eq!(plan.sample(-1.0).position, start.position);
}

#[test]
fn the_index_is_the_point_last_reached() {
    let t = moveit(false);
    let plan = Plan::new(&t, &joints(), at_rest([0.0; 6]), T0, DT).unwrap();
    assert_eq!(plan.index_at(-1.0), 0);
    assert_eq!(plan.index_at(0.05), 0);
    assert_eq!(plan.index_at(0.1), 1);
    assert_eq!(plan.index_at(1.04), 10);
    assert_eq!(plan.index_at(5.0), 20);
}

/// A position-only trajectory from rest at point 0: times with random gaps, random positions.
fn random_trajectory() -> impl Strategy<Value = JointTrajectory> {
    prop::collection::vec((0.02..1.0f64, prop::array::uniform6(-1.0..1.0f64)), 1..8).prop_map(
        |steps| {
            let mut t = 0.0;
            let mut points = vec![point(0.0, [0.0; 6])];
            for (gap, p) in steps {
                t += gap;
                points.push(point(t, p));
            }
            traj(points)
        },
    )
}

proptest! {
    /// With limits out of the way: every sample is finite, and (estimated velocities being
    /// monotone) lies between the positions of the two knots around it.
    #[test]
    fn random_position_only_trajectories_stay_between_their_knots(t in random_trajectory()) {
        let plan = Plan::new(&t, &loose_joints(), at_rest([0.0; 6]), T0, DT).unwrap();
        let knot_times = times(&t);
        let mut tt = -0.05;
        while tt < plan.duration() + 0.05 {
            let s = plan.sample(tt);
            let k = knot_times.partition_point(|&x| x <= tt).clamp(1, knot_times.len() - 1);
            for i in 0..6 {
                prop_assert!(s.position[i].is_finite() && s.velocity[i].is_finite());
                prop_assert!(s.acceleration[i].is_finite());
                let (a, b) = (t.points[k - 1].positions[i], t.points[k].positions[i]);
                let (lo, hi) = (a.min(b) - 1e-12, a.max(b) + 1e-12);
                prop_assert!(
                    s.position[i] >= lo && s.position[i] <= hi,
                    "t {} axis {} position {} outside [{}, {}]", tt, i, s.position[i], lo, hi
                );
            }
            tt += 0.0037;
        }
        prop_assert_eq!(plan.pvt_point(plan.point_count() - 1).position_deg,
            plan.final_state().position.map(f64::to_degrees));
    }
}

/// Any value a goal may carry, the awkward ones often.
fn any_value() -> impl Strategy<Value = f64> {
    prop_oneof![
        -4.0..4.0f64,
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(1e300),
        Just(-0.0),
        any::<f64>(),
    ]
}

fn any_goal_trajectory() -> impl Strategy<Value = JointTrajectory> {
    let names = prop::collection::vec(
        prop_oneof![
            prop::sample::select(vec![
                "base", "shoulder", "elbow", "forearm", "wrist", "flange"
            ])
            .prop_map(str::to_string),
            ".{0,8}",
        ],
        0..8,
    );
    let vector = || prop::collection::vec(any_value(), 0..8);
    let time = prop_oneof![(0i32..20, any::<u32>()), (any::<i32>(), any::<u32>()),];
    let points = prop::collection::vec((vector(), vector(), vector(), time), 0..6);
    let stamp = prop_oneof![Just((0i32, 0u32)), (any::<i32>(), any::<u32>())];
    (names, points, stamp).prop_map(|(names, points, (sec, nanosec))| {
        let mut t = traj(
            points
                .into_iter()
                .map(|(p, v, a, (sec, nanosec))| JointTrajectoryPoint {
                    positions: p.into(),
                    velocities: v.into(),
                    accelerations: a.into(),
                    effort: Default::default(),
                    time_from_start: crate::msgs::builtin::Duration { sec, nanosec },
                })
                .collect(),
        );
        t.joint_names = names.into();
        t.header.stamp = Time { sec, nanosec };
        t
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    /// A goal is input from the network: whatever it holds (unknown or repeated names, any
    /// lengths, NaN and infinities, any times and stamps), planning answers Ok or a GoalError
    /// with a code, and never panics or runs away (a trajectory lasts at most MAX_DURATION_S).
    #[test]
    fn any_goal_is_planned_or_refused_never_a_panic(t in any_goal_trajectory()) {
        match Plan::new(&t, &joints(), at_rest([0.0; 6]), T0, DT) {
            Ok(plan) => {
                prop_assert!(plan.duration() <= crate::trajectory::MAX_DURATION_S);
                if plan.point_count() > 0 {
                    let p = plan.pvt_point(plan.point_count() - 1);
                    prop_assert!(p.position_deg.iter().all(|x| x.is_finite()));
                }
            }
            Err(e) => {
                prop_assert!(e.code() < 0);
                prop_assert!(!e.to_string().is_empty());
            }
        }
    }
}

/// A trajectory far longer than MAX_DURATION_S is refused at once, naming its length.
#[test]
fn a_trajectory_of_hours_is_refused_before_it_is_sampled() {
    let t = traj(vec![point(0.0, [0.0; 6]), point(3600.0 * 24.0, [0.1; 6])]);
    let e = Plan::new(&t, &joints(), at_rest([0.0; 6]), T0, DT).unwrap_err();
    assert_eq!(e.code(), crate::msgs::control::error_code::INVALID_GOAL);
    assert!(e.to_string().contains("86400.000 s from now"), "{e}");
    assert!(e.to_string().contains("at most 600 s"), "{e}");
}
