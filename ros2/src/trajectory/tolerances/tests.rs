use super::super::tests::joints;
use super::*;
use crate::msgs::builtin::Duration;
use crate::msgs::control::JointComponentTolerance;

fn tolerance(name: &str, position: f64, velocity: f64) -> JointTolerance {
    JointTolerance {
        name: name.into(),
        position,
        velocity,
        acceleration: 0.0,
    }
}

fn parse(goal: &FollowJointTrajectoryGoal) -> Result<Tolerances, GoalError> {
    Tolerances::from_goal(goal, &joints(), &ToleranceDefaults::default())
}

#[test]
fn zero_is_the_default_minus_one_no_limit_and_a_value_that_bound() {
    let goal = FollowJointTrajectoryGoal {
        path_tolerance: vec![tolerance("elbow", 0.0, -1.0), tolerance("wrist", -1.0, 0.2)].into(),
        goal_tolerance: vec![tolerance("flange", 0.002, 0.0)].into(),
        ..Default::default()
    };
    let t = parse(&goal).unwrap();
    let d = ToleranceDefaults::default();
    assert_eq!(
        t.path(2).position,
        d.path_position,
        "elbow: 0 is the default"
    );
    assert_eq!(t.path(2).velocity, None, "elbow: -1 is no limit");
    assert_eq!(t.path(4).position, None);
    assert_eq!(t.path(4).velocity, Some(0.2));
    assert_eq!(
        t.path(0).position,
        Some(0.05),
        "a joint not named has the defaults"
    );
    assert_eq!(t.goal(5).position, Some(0.002));
    assert_eq!(t.goal(5).velocity, Some(0.01));
    assert_eq!(t.goal_time(), 0.5, "goal_time_tolerance 0 is the default");
}

#[test]
fn the_goal_time_tolerance_is_taken_or_refused() {
    let mut goal = FollowJointTrajectoryGoal {
        goal_time_tolerance: Duration::from_secs_f64(1.25),
        ..Default::default()
    };
    assert_eq!(parse(&goal).unwrap().goal_time(), 1.25);
    goal.goal_time_tolerance = Duration::from_secs_f64(-0.5);
    let e = parse(&goal).unwrap_err();
    assert_eq!(e.code(), error_code::INVALID_GOAL);
    assert_eq!(
        e.to_string(),
        "goal_time_tolerance -0.5 s is not allowed; it must be 0 (the default) or positive"
    );
}

#[test]
fn a_tolerance_of_an_unknown_joint_is_invalid_joints() {
    let goal = FollowJointTrajectoryGoal {
        goal_tolerance: vec![tolerance("knee", 0.1, 0.0)].into(),
        ..Default::default()
    };
    let e = parse(&goal).unwrap_err();
    assert_eq!(e.code(), error_code::INVALID_JOINTS);
    assert_eq!(
        e.to_string(),
        "goal_tolerance names the joint \"knee\", which the arm does not have; its joints are \
         base, shoulder, elbow, forearm, wrist, flange"
    );
    let goal = FollowJointTrajectoryGoal {
        component_path_tolerance: vec![JointComponentTolerance {
            joint_name: "base".into(),
            ..Default::default()
        }]
        .into(),
        ..Default::default()
    };
    assert_eq!(parse(&goal).unwrap_err().code(), error_code::INVALID_JOINTS);
}

#[test]
fn a_negative_tolerance_other_than_minus_one_is_invalid() {
    for bad in [-0.5, -2.0, f64::NAN, f64::INFINITY] {
        let goal = FollowJointTrajectoryGoal {
            path_tolerance: vec![tolerance("shoulder", 0.0, bad)].into(),
            ..Default::default()
        };
        let e = parse(&goal).unwrap_err();
        assert_eq!(e.code(), error_code::INVALID_GOAL, "{bad}");
        assert!(
            e.to_string().starts_with(&format!(
                "path_tolerance of joint \"shoulder\": velocity {bad} is not allowed"
            )),
            "{e}"
        );
    }
}

#[test]
fn the_path_check_names_joint_quantity_error_and_tolerance() {
    let t = parse(&FollowJointTrajectoryGoal::default()).unwrap();
    let desired = Sample {
        position: [0.1; 6],
        ..Default::default()
    };
    let mut actual = [0.1; 6];
    actual[3] = 0.14;
    assert!(
        t.check_path(&desired, &actual, &[5.0; 6]).is_ok(),
        "speed unchecked"
    );
    actual[3] = 0.2;
    let v = t.check_path(&desired, &actual, &[0.0; 6]).unwrap_err();
    assert_eq!(
        (v.phase, v.joint.as_str(), v.quantity),
        (Phase::Path, "forearm", Quantity::Position)
    );
    assert!((v.error - 0.1).abs() < 1e-12);
    assert_eq!(v.code(), error_code::PATH_TOLERANCE_VIOLATED);
    assert!(v.to_string().starts_with(
        "path tolerance violated: joint \"forearm\" position error 0.1 rad (5.72957795131 deg) \
         exceeds the tolerance 0.05 rad (2.86478897565 deg)"
    ));
}

#[test]
fn the_goal_check_wants_the_final_position_at_rest() {
    let t = parse(&FollowJointTrajectoryGoal::default()).unwrap();
    let fin = Sample {
        position: [0.5; 6],
        ..Default::default()
    };
    assert!(t.check_goal(&fin, &[0.505; 6], &[0.005; 6]).is_ok());
    let v = t
        .check_goal(&fin, &[0.5; 6], &[0.0, 0.0, -0.02, 0.0, 0.0, 0.0])
        .unwrap_err();
    assert_eq!((v.phase, v.quantity), (Phase::Goal, Quantity::Velocity));
    assert_eq!(v.code(), error_code::GOAL_TOLERANCE_VIOLATED);
    assert!(
        v.to_string()
            .contains("joint \"elbow\" velocity error -0.02 rad/s"),
        "{v}"
    );
    assert!(
        t.check_goal(&fin, &[f64::NAN; 6], &[0.0; 6]).is_err(),
        "NaN is never within"
    );
}

use proptest::prelude::Strategy as _;

proptest::proptest! {
    /// Tolerances come from the network: any names and values (NaN, infinities, negative
    /// values, any goal time) are parsed or refused with a code, and the checks never panic on
    /// what was parsed.
    #[test]
    fn any_tolerances_are_parsed_or_refused_never_a_panic(
        entries in proptest::collection::vec(
            (
                proptest::prop_oneof![
                    proptest::sample::select(vec!["base", "elbow", "flange"]).prop_map(str::to_string),
                    ".{0,6}",
                ],
                proptest::num::f64::ANY,
                proptest::num::f64::ANY,
                proptest::num::f64::ANY,
            ),
            0..6,
        ),
        goal_time in (proptest::prelude::any::<i32>(), proptest::prelude::any::<u32>()),
        position in proptest::array::uniform6(proptest::num::f64::ANY),
    ) {
        let tol: Vec<JointTolerance> = entries
            .iter()
            .map(|(name, p, v, a)| JointTolerance { name: name.clone(), position: *p, velocity: *v, acceleration: *a })
            .collect();
        let goal = FollowJointTrajectoryGoal {
            path_tolerance: tol.clone().into(),
            goal_tolerance: tol.into(),
            goal_time_tolerance: Duration { sec: goal_time.0, nanosec: goal_time.1 },
            ..Default::default()
        };
        match parse(&goal) {
            Ok(t) => {
                let s = crate::trajectory::Sample::default();
                let _ = t.check_path(&s, &position, &position);
                let _ = t.check_goal(&s, &position, &position);
                proptest::prop_assert!(t.goal_time() >= 0.0);
            }
            Err(e) => proptest::prop_assert!(e.code() < 0),
        }
    }
}
