use super::{MAX_JOINTS, MAX_POINTS, check_size};
use crate::msgs::control::FollowJointTrajectoryGoal;
use crate::msgs::trajectory::JointTrajectoryPoint;
use crate::trajectory::GoalError;

fn goal(points: usize) -> FollowJointTrajectoryGoal {
    let mut g = FollowJointTrajectoryGoal::default();
    g.trajectory.points = vec![JointTrajectoryPoint::default(); points].into();
    g
}

#[test]
fn a_goal_at_the_limits_passes() {
    assert_eq!(check_size(&goal(MAX_POINTS)), Ok(()));
}

#[test]
fn one_point_more_is_refused_naming_the_limit() {
    let e = check_size(&goal(MAX_POINTS + 1)).expect_err("over the limit");
    assert_eq!(
        e,
        GoalError::Oversize {
            field: "trajectory.points".into(),
            len: MAX_POINTS + 1,
            max: MAX_POINTS
        }
    );
    assert_eq!(
        e.to_string(),
        "trajectory.points has 10001 entries; allowed: at most 10000 (docs/ros2.md, limits)"
    );
}

#[test]
fn a_long_per_joint_sequence_is_refused_with_its_place() {
    let mut g = goal(3);
    g.trajectory.points[2].velocities = vec![0.0; MAX_JOINTS + 1].into();
    let e = check_size(&g).expect_err("over the limit");
    assert!(
        e.to_string()
            .starts_with("trajectory.points[2].velocities has 65 entries; allowed: at most 64"),
        "{e}"
    );
    let mut g = goal(1);
    g.goal_tolerance = vec![Default::default(); MAX_JOINTS + 1].into();
    assert!(check_size(&g).is_err());
}

#[test]
fn the_plan_refuses_an_oversize_trajectory_itself() {
    use crate::trajectory::tests::{joints, traj};
    use crate::trajectory::{Plan, StartState};
    // As it arrives over DDS: the length as sent, no element kept.
    let sent = vec![JointTrajectoryPoint::default(); MAX_POINTS + 1];
    let bytes = cdr_encoding::to_vec::<_, byteorder::LittleEndian>(&sent).expect("encodes");
    let points = cdr_encoding::from_bytes::<_, byteorder::LittleEndian>(&bytes)
        .expect("decodes")
        .0;
    let mut t = traj(Vec::new());
    t.points = points;
    let e = Plan::new(
        &t,
        &joints(),
        StartState::default(),
        crate::msgs::builtin::Time::default(),
        0.005,
    )
    .expect_err("oversize");
    assert!(
        matches!(e, GoalError::Oversize { len, .. } if len == MAX_POINTS + 1),
        "{e}"
    );
}
