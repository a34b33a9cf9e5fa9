use super::{FeedbackOnWire, FollowJointTrajectoryFeedback};
use crate::distro::RosDistro;
use crate::msgs::trajectory::JointTrajectoryPoint;
use cdr_encoding::to_vec;

type Le = byteorder::LittleEndian;

fn feedback() -> FollowJointTrajectoryFeedback {
    let point = |x: f64| JointTrajectoryPoint {
        positions: vec![x, x + 1.0].into(),
        ..Default::default()
    };
    FollowJointTrajectoryFeedback {
        joint_names: vec!["base".into(), "shoulder".into()],
        desired: point(1.0),
        actual: point(2.0),
        error: point(3.0),
        index: 7,
        multi_dof_joint_names: vec!["none".into()],
        multi_dof_index: 9,
        ..Default::default()
    }
}

fn on_wire(distro: RosDistro) -> Vec<u8> {
    to_vec::<_, Le>(&FeedbackOnWire {
        distro,
        feedback: feedback(),
    })
    .expect("encodes")
}

/// control_msgs 6.x (Kilted, Lyrical): `index` after `error`, `multi_dof_index` at the end.
#[test]
fn kilted_and_lyrical_send_the_indices() {
    let f = feedback();
    let want = to_vec::<_, Le>(&(
        &f.header,
        &f.joint_names,
        &f.desired,
        &f.actual,
        &f.error,
        7i32,
        &f.multi_dof_joint_names,
        &f.multi_dof_desired,
        &f.multi_dof_actual,
        &f.multi_dof_error,
        9i32,
    ))
    .expect("encodes");
    assert_eq!(on_wire(RosDistro::Kilted), want);
    assert_eq!(on_wire(RosDistro::Lyrical), want);
}

/// control_msgs 5.x (Jazzy): neither index.
#[test]
fn jazzy_sends_no_index() {
    let f = feedback();
    let want = to_vec::<_, Le>(&(
        &f.header,
        &f.joint_names,
        &f.desired,
        &f.actual,
        &f.error,
        &f.multi_dof_joint_names,
        &f.multi_dof_desired,
        &f.multi_dof_actual,
        &f.multi_dof_error,
    ))
    .expect("encodes");
    assert_eq!(on_wire(RosDistro::Jazzy), want);
}
