//! Goal validation through `Plan::new`: each refusal's code and words. Helpers shared with the
//! submodules' tests.

use super::*;
use crate::msgs::builtin::{Duration, Time};
use crate::msgs::control::error_code;
use crate::msgs::trajectory::{JointTrajectory, JointTrajectoryPoint};
use mcm_shared::config::RobotConfig;

pub(super) const DT: f64 = 0.01;

/// The ROS time at the plan's t = 0 in these tests.
pub(super) const T0: Time = Time {
    sec: 1_000,
    nanosec: 0,
};

/// The P-Rob2's joints, unprefixed: base, shoulder, elbow, forearm, wrist, flange.
pub(super) fn joints() -> Joints {
    Joints::from_config(&RobotConfig::prob2_default(), "").unwrap()
}

/// Joints with limits so wide that only the shape of a path matters.
pub(super) fn loose_joints() -> Joints {
    let mut cfg = RobotConfig::prob2_default();
    for a in &mut cfg.axes {
        a.max_velocity_deg_s = 1e9;
        a.max_acceleration_deg_s2 = 1e12;
    }
    Joints::from_config(&cfg, "").unwrap()
}

pub(super) fn point(t: f64, positions: [f64; 6]) -> JointTrajectoryPoint {
    JointTrajectoryPoint {
        positions: positions.to_vec().into(),
        time_from_start: Duration::from_secs_f64(t),
        ..Default::default()
    }
}

pub(super) fn point_pv(t: f64, positions: [f64; 6], velocities: [f64; 6]) -> JointTrajectoryPoint {
    JointTrajectoryPoint {
        velocities: velocities.to_vec().into(),
        ..point(t, positions)
    }
}

/// A trajectory naming the joints in axis order, stamped 0 ("start now").
pub(super) fn traj(points: Vec<JointTrajectoryPoint>) -> JointTrajectory {
    JointTrajectory {
        joint_names: joints().names().to_vec().into(),
        points: points.into(),
        ..Default::default()
    }
}

pub(super) fn at_rest(position: [f64; 6]) -> StartState {
    StartState {
        position,
        velocity: [0.0; 6],
    }
}

fn refusal(t: &JointTrajectory, start: StartState) -> GoalError {
    Plan::new(t, &joints(), start, T0, DT).expect_err("the goal must be refused")
}

/// A small motion of every joint that stays well within the limits.
fn easy() -> JointTrajectory {
    traj(vec![
        point(0.0, [0.0; 6]),
        point(1.0, [0.1, 0.2, -0.1, 0.05, 0.1, -0.2]),
        point(2.0, [0.2, 0.1, -0.2, 0.0, 0.2, 0.0]),
    ])
}

#[test]
fn the_easy_goal_is_accepted() {
    let plan = Plan::new(&easy(), &joints(), at_rest([0.0; 6]), T0, DT).unwrap();
    assert_eq!(plan.duration(), 2.0);
    assert_eq!(plan.point_count(), 200);
}

#[test]
fn reordered_joint_names_map_to_the_right_axes() {
    let mut t = easy();
    // Name the joints last to first, and write every vector that way.
    t.joint_names.reverse();
    for p in &mut t.points {
        p.positions.reverse();
    }
    let plan = Plan::new(&t, &joints(), at_rest([0.0; 6]), T0, DT).unwrap();
    assert_eq!(
        plan.final_state().position,
        [0.2, 0.1, -0.2, 0.0, 0.2, 0.0],
        "axis order"
    );
    assert_eq!(plan.sample(1.0).position, [0.1, 0.2, -0.1, 0.05, 0.1, -0.2]);
}

#[test]
fn joint_names_that_are_not_the_arms_are_invalid_joints() {
    let mut t = easy();
    t.joint_names[1] = "knee".into();
    t.joint_names[2] = "base".into();
    let e = refusal(&t, at_rest([0.0; 6]));
    assert_eq!(e.code(), error_code::INVALID_JOINTS);
    let m = e.to_string();
    for words in [
        "unknown: \"knee\"",
        "missing: \"shoulder\", \"elbow\"",
        "named more than once: \"base\"",
        "base, shoulder, elbow, forearm, wrist, flange",
    ] {
        assert!(m.contains(words), "{m:?} lacks {words:?}");
    }
    let mut t = easy();
    t.joint_names.pop();
    let e = refusal(&t, at_rest([0.0; 6]));
    assert_eq!(e.code(), error_code::INVALID_JOINTS);
    assert!(e.to_string().contains("missing: \"flange\""), "{e}");
}

#[test]
fn a_prefix_names_the_joints() {
    let j = Joints::from_config(&RobotConfig::prob2_default(), "prob2_").unwrap();
    assert_eq!(j.name(0), "prob2_base");
    assert_eq!(j.axis_of("prob2_flange"), Some(5));
    assert_eq!(j.axis_of("flange"), None);
}

#[test]
fn a_goal_without_points_is_invalid() {
    let e = refusal(&traj(vec![]), at_rest([0.0; 6]));
    assert_eq!(e.code(), error_code::INVALID_GOAL);
    assert!(e.to_string().contains("no points"), "{e}");
}

#[test]
fn times_must_increase_strictly() {
    let mut t = easy();
    t.points[2].time_from_start = t.points[1].time_from_start;
    let e = refusal(&t, at_rest([0.0; 6]));
    assert_eq!(e.code(), error_code::INVALID_GOAL);
    assert_eq!(
        e.to_string(),
        "point 2: time_from_start 1 s is not after point 1's 1 s; the times must increase strictly"
    );
    let mut t = easy();
    t.points[0].time_from_start = Duration {
        sec: -1,
        nanosec: 500_000_000,
    };
    let e = refusal(&t, at_rest([0.0; 6]));
    assert!(
        e.to_string().contains("time_from_start -0.5 s is negative"),
        "{e}"
    );
}

#[test]
fn vectors_must_have_one_value_per_joint() {
    let mut t = easy();
    t.points[1].positions.pop();
    let e = refusal(&t, at_rest([0.0; 6]));
    assert_eq!(e.code(), error_code::INVALID_GOAL);
    assert_eq!(
        e.to_string(),
        "point 1: positions has 5 values; it must have one per joint (6)"
    );
    let mut t = easy();
    t.points[2].velocities = vec![0.0; 3].into();
    let e = refusal(&t, at_rest([0.0; 6]));
    assert!(
        e.to_string()
            .contains("velocities has 3 values; it must have none or one per joint")
    );
    let mut t = easy();
    t.points[2].accelerations = vec![0.0; 7].into();
    assert!(matches!(
        refusal(&t, at_rest([0.0; 6])),
        GoalError::Length {
            index: 2,
            field: "accelerations",
            len: 7,
            ..
        }
    ));
}

#[test]
fn values_must_be_finite() {
    let mut t = easy();
    t.points[1].positions[2] = f64::NAN;
    let e = refusal(&t, at_rest([0.0; 6]));
    assert_eq!(e.code(), error_code::INVALID_GOAL);
    assert_eq!(
        e.to_string(),
        "point 1: positions of joint \"elbow\" is NaN; every value must be finite"
    );
    let mut t = easy();
    t.points[2].velocities = vec![0.0, 0.0, 0.0, f64::INFINITY, 0.0, 0.0].into();
    assert!(
        refusal(&t, at_rest([0.0; 6]))
            .to_string()
            .contains("\"forearm\" is inf")
    );
}

#[test]
fn a_position_outside_the_reachable_range_is_invalid() {
    // The shoulder's limits are ±120°, less the 1° margin: 2.1 rad (120.3°) is out.
    let mut t = easy();
    t.points[1].positions[1] = 2.1;
    let e = refusal(&t, at_rest([0.0; 6]));
    assert_eq!(e.code(), error_code::INVALID_GOAL);
    let m = e.to_string();
    assert!(
        m.starts_with("point 1: position of joint \"shoulder\" 2.1 rad (120.32"),
        "{m}"
    );
    assert!(m.contains("outside its reachable range -2.07694"), "{m}");
    assert!(m.contains("(-119 deg) to 2.07694"), "{m}");
    assert!(m.contains("(119 deg)"), "{m}");
}

#[test]
fn a_first_point_at_time_0_must_be_the_start() {
    let mut t = easy();
    t.points[0].positions[4] = 0.02;
    let e = refusal(&t, at_rest([0.0; 6]));
    assert_eq!(e.code(), error_code::INVALID_GOAL);
    let m = e.to_string();
    assert!(m.contains("joint \"wrist\" is at 0.02 rad"), "{m}");
    assert!(
        m.contains("and at 0 rad (0 deg) in the arm's start state"),
        "{m}"
    );
    assert!(m.contains("more than the 0.01 rad"), "{m}");
    // Within the tolerance the start state takes its place: the plan starts exactly there.
    t.points[0].positions[4] = 0.009;
    let plan = Plan::new(&t, &joints(), at_rest([0.0; 6]), T0, DT).unwrap();
    assert_eq!(plan.sample(0.0).position, [0.0; 6]);
}

#[test]
fn a_trajectory_too_fast_for_the_axes_is_refused_naming_the_limit() {
    // Base: 0.5 rad in 0.3 s needs more than its 90 deg/s (1.5708 rad/s).
    let t = traj(vec![
        point(0.0, [0.0; 6]),
        point(0.3, [0.5, 0.0, 0.0, 0.0, 0.0, 0.0]),
    ]);
    let e = refusal(&t, at_rest([0.0; 6]));
    assert_eq!(e.code(), error_code::INVALID_GOAL);
    let GoalError::Limit {
        ref joint,
        quantity,
        value,
        limit,
        ..
    } = e
    else {
        panic!("{e:?}")
    };
    assert_eq!(joint, "base");
    assert!(
        quantity == Quantity::Velocity || quantity == Quantity::Acceleration,
        "{e}"
    );
    assert!(value.abs() > limit);
    let m = e.to_string();
    assert!(m.contains("joint \"base\""), "{m}");
    assert!(m.contains("exceeds the limit"), "{m}");
    assert!(m.contains("deg/s"), "{m}");
}

#[test]
fn a_speed_over_the_limit_is_caught_where_the_acceleration_is_not() {
    // Slow enough to accelerate, but 2 rad at a steady ~2 rad/s exceeds 90 deg/s.
    let v = 2.0;
    let t = traj(vec![
        point(0.0, [0.0; 6]),
        point_pv(
            1.0,
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [v, 0.0, 0.0, 0.0, 0.0, 0.0],
        ),
        point_pv(
            1.5,
            [2.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [v, 0.0, 0.0, 0.0, 0.0, 0.0],
        ),
        point(3.0, [2.5, 0.0, 0.0, 0.0, 0.0, 0.0]),
    ]);
    let e = Plan::new(&t, &loose_acceleration(), at_rest([0.0; 6]), T0, DT).unwrap_err();
    assert!(
        matches!(
            e,
            GoalError::Limit {
                quantity: Quantity::Velocity,
                pvt: None,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains("exceeds the limit 1.57079632679 rad/s (90 deg/s)"),
        "{e}"
    );
}

fn loose_acceleration() -> Joints {
    let mut cfg = RobotConfig::prob2_default();
    for a in &mut cfg.axes {
        a.max_acceleration_deg_s2 = 1e9;
    }
    Joints::from_config(&cfg, "").unwrap()
}

#[test]
fn an_acceleration_over_the_limit_is_caught() {
    // Elbow: 0.1 rad in 0.2 s from rest to rest needs 6·0.1/0.2² = 15 rad/s² at the start.
    let t = traj(vec![
        point(0.0, [0.0; 6]),
        point(0.2, [0.0, 0.0, 0.1, 0.0, 0.0, 0.0]),
    ]);
    let e = refusal(&t, at_rest([0.0; 6]));
    let GoalError::Limit {
        ref joint,
        quantity: Quantity::Acceleration,
        time,
        value,
        ..
    } = e
    else {
        panic!("{e:?}")
    };
    assert_eq!((joint.as_str(), time), ("elbow", 0.0));
    assert!((value - 15.0).abs() < 1e-9, "{value}");
    assert!(
        e.to_string().contains("acceleration 15 rad/s^2 (859.43"),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("limit 3.14159265359 rad/s^2 (180 deg/s^2)"),
        "{e}"
    );
}

#[test]
fn the_cores_interpolation_of_the_pvt_points_is_checked_too() {
    // Bang-bang on the base: +A for h, then -A for h (two cubic segments with c3 = 0), A at
    // 90 % of the limit. The plan passes; the acceleration steps in the middle of a PVT
    // interval (h = 25.5·dt), and the core's cubic through the points around the step needs
    // about 1.5·A there: more than the limit.
    let a = 0.9 * 180f64.to_radians();
    let e = refusal(&bang_bang(0.255, a), at_rest([0.0; 6]));
    let GoalError::Limit {
        quantity: Quantity::Acceleration,
        pvt: Some(k),
        value,
        ..
    } = e
    else {
        panic!("{e:?}")
    };
    assert!(k == 25 || k == 26, "{k}");
    assert!(value.abs() > 1.3 * a, "{value}");
    assert!(
        e.to_string()
            .contains("as the core interpolates the PVT points"),
        "{e}"
    );
    // With the step on a PVT point (h = 25·dt) the core's cubics follow the plan: accepted.
    Plan::new(&bang_bang(0.25, a), &joints(), at_rest([0.0; 6]), T0, DT).unwrap();
}

/// The base from rest at +a for h seconds, then at -a to rest.
fn bang_bang(h: f64, a: f64) -> JointTrajectory {
    let (vm, mid) = (a * h, a * h * h / 2.0);
    traj(vec![
        point(0.0, [0.0; 6]),
        point_pv(
            h,
            [mid, 0.0, 0.0, 0.0, 0.0, 0.0],
            [vm, 0.0, 0.0, 0.0, 0.0, 0.0],
        ),
        point(2.0 * h, [2.0 * mid, 0.0, 0.0, 0.0, 0.0, 0.0]),
    ])
}

#[test]
fn a_trajectory_that_ended_before_the_start_has_an_old_header_timestamp() {
    let mut t = easy();
    t.header.stamp = Time {
        sec: T0.sec - 10,
        nanosec: 0,
    };
    let e = refusal(&t, at_rest([0.0; 6]));
    assert_eq!(e.code(), error_code::OLD_HEADER_TIMESTAMP);
    assert_eq!(
        e.to_string(),
        "the trajectory ends at header.stamp 990 s + 2 s, 8 s before the arm can start it; \
         a stamp must be 0 (start now) or leave the trajectory's end in the future"
    );
}

#[test]
fn a_past_stamp_skips_the_points_already_past() {
    let mut t = easy();
    // 0.5 s late: point 0 is past; point 1 comes 0.5 s after the start, point 2 1.5 s
    // (faster than the goal meant: the shoulder's 0.2 rad in 0.5 s would break its
    // acceleration limit, so the limits are wide here).
    t.header.stamp = Time {
        sec: T0.sec - 1,
        nanosec: 500_000_000,
    };
    let e = refusal(&t, at_rest([0.0; 6]));
    assert!(
        matches!(
            e,
            GoalError::Limit {
                quantity: Quantity::Acceleration,
                ..
            }
        ),
        "{e}"
    );
    let plan = Plan::new(&t, &loose_joints(), at_rest([0.0; 6]), T0, DT).unwrap();
    assert_eq!(plan.offset(), -0.5);
    assert_eq!(plan.duration(), 1.5);
    assert_eq!(plan.sample(0.5).position, [0.1, 0.2, -0.1, 0.05, 0.1, -0.2]);
    assert_eq!(plan.index_at(0.0), 0);
    assert_eq!(plan.index_at(0.6), 1);
    assert_eq!(plan.time_from_start(0.6), 1.1);
}

#[test]
fn a_future_stamp_holds_the_start_until_then() {
    let mut t = easy();
    t.header.stamp = Time {
        sec: T0.sec,
        nanosec: 300_000_000,
    };
    let start = [0.001, 0.0, 0.0, 0.0, 0.0, 0.0];
    let plan = Plan::new(&t, &joints(), at_rest(start), T0, DT).unwrap();
    assert_eq!(plan.duration(), 2.3);
    for tt in [0.0, 0.1, 0.2, 0.3] {
        let s = plan.sample(tt);
        assert_eq!((s.position, s.velocity), (start, [0.0; 6]), "at {tt}");
    }
    assert_eq!(plan.sample(1.3).position, [0.1, 0.2, -0.1, 0.05, 0.1, -0.2]);
    assert_eq!(plan.index_at(0.2), 0);
    assert_eq!(plan.index_at(1.35), 1);
    assert_eq!(plan.index_at(9.0), 2);
}

#[test]
fn a_trajectory_that_is_only_its_start_is_done_at_rest_and_refused_moving() {
    let t = traj(vec![point(0.0, [0.0; 6])]);
    let plan = Plan::new(&t, &joints(), at_rest([0.0; 6]), T0, DT).unwrap();
    assert_eq!((plan.duration(), plan.point_count()), (0.0, 0));
    let moving = StartState {
        position: [0.0; 6],
        velocity: [0.0, 0.0, 0.3, 0.0, 0.0, 0.0],
    };
    let e = refusal(&t, moving);
    assert_eq!(e.code(), error_code::INVALID_GOAL);
    assert!(
        e.to_string().contains("joint \"elbow\" moves at 0.3 rad/s"),
        "{e}"
    );
}

#[test]
fn a_bad_dt_or_start_state_is_refused() {
    let e = Plan::new(&easy(), &joints(), at_rest([0.0; 6]), T0, 0.0).unwrap_err();
    assert!(e.to_string().contains("dt = 0 s is not allowed"), "{e}");
    let mut start = at_rest([0.0; 6]);
    start.velocity[3] = f64::NAN;
    let e = refusal(&easy(), start);
    assert_eq!(
        e.to_string(),
        "the start state's velocity of joint \"forearm\" is NaN; it must be finite"
    );
}
