//! The pose arguments of `inverse_kinematics` and `move_to_pose`: what is refused, in which
//! words, and what is normalised.

use crate::config::RobotConfig;
use crate::error_code::ErrorCode;
use crate::protocol::{Command, CommandError, InverseKinematics, MoveToPose, Pose};

fn parse(text: &str) -> Result<Command, CommandError> {
    Command::from_json(text, &RobotConfig::prob2_default())
}

fn ik(arguments: &str) -> Result<Command, CommandError> {
    parse(&format!(
        r#"{{"command":"inverse_kinematics","arguments":{arguments}}}"#
    ))
}

#[test]
fn a_pose_and_a_seed_read_as_given() {
    let c = ik(r#"{"position":[0.4,0,0.5],"orientation":[0,1,0,0],"seed":[0,10,20,0,-5,0]}"#);
    assert_eq!(
        c.unwrap(),
        Command::InverseKinematics(InverseKinematics {
            pose: Pose {
                position: [0.4, 0.0, 0.5],
                orientation: [0.0, 1.0, 0.0, 0.0],
            },
            seed_deg: Some([0.0, 10.0, 20.0, 0.0, -5.0, 0.0]),
        })
    );
    let Ok(Command::MoveToPose(m)) = parse(
        r#"{"command":"move_to_pose","arguments":{"position":[0.4,0,0.5],"orientation":[0,0,0,1]}}"#,
    ) else {
        panic!("move_to_pose does not parse");
    };
    assert_eq!(
        m,
        MoveToPose {
            pose: Pose {
                position: [0.4, 0.0, 0.5],
                orientation: [0.0, 0.0, 0.0, 1.0],
            },
            velocity_factor: crate::protocol::DEFAULT_VELOCITY_FACTOR,
        }
    );
}

/// A quaternion a little off unit (rounded figures) is normalised; one farther off is refused,
/// naming its norm and the tolerance.
#[test]
fn a_quaternion_near_unit_is_normalised_and_one_that_is_not_is_refused() {
    let Ok(Command::InverseKinematics(c)) =
        ik(r#"{"position":[0.4,0,0.5],"orientation":[0.7071,0,0,0.7071]}"#)
    else {
        panic!("a quaternion of norm 0.99999 is refused");
    };
    let q = c.pose.orientation;
    let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!((norm - 1.0).abs() < 1e-15, "{q:?}");
    assert!((q[0] - q[3]).abs() < 1e-15 && q[1] == 0.0, "{q:?}");

    let e = ik(r#"{"position":[0.4,0,0.5],"orientation":[0,0,0,0.5]}"#).unwrap_err();
    assert_eq!(e.code(), ErrorCode::InvalidArgument);
    assert_eq!(
        e.to_string(),
        "inverse_kinematics: argument \"orientation\" = [0,0,0,0.5] is not allowed; expected a \
         unit quaternion [x, y, z, w]: its norm is 0.5, not within 0.001 of 1"
    );
    let e = ik(r#"{"position":[0.4,0,0.5],"orientation":[0,0,0,0]}"#).unwrap_err();
    assert!(e.to_string().contains("its norm is 0, not within"), "{e}");
}

#[test]
fn a_missing_or_malformed_position_is_refused_naming_it() {
    let e = ik(r#"{"orientation":[0,0,0,1]}"#).unwrap_err();
    assert_eq!(e.code(), ErrorCode::MissingArgument);
    assert_eq!(
        e.to_string(),
        "inverse_kinematics: missing argument \"position\" (an array of 3 coordinates x, y, z [m])"
    );
    let e = ik(r#"{"position":[0.4,0],"orientation":[0,0,0,1]}"#).unwrap_err();
    assert_eq!(e.code(), ErrorCode::InvalidArgument);
    assert_eq!(
        e.to_string(),
        "inverse_kinematics: argument \"position\" = [0.4,0] is not allowed; expected an array \
         of 3 coordinates x, y, z [m]"
    );
    let e = ik(r#"{"position":[0.4,"x",0],"orientation":[0,0,0,1]}"#).unwrap_err();
    assert_eq!(
        e.to_string(),
        "inverse_kinematics: argument \"position[1]\" = \"x\" is not allowed; expected a number \
         (coordinates x, y, z [m])"
    );
    let e = ik(r#"{"position":[0.4,0,0.5]}"#).unwrap_err();
    assert_eq!(
        e.to_string(),
        "inverse_kinematics: missing argument \"orientation\" (an array of 4 quaternion \
         components x, y, z, w)"
    );
    let e = ik(r#"{"position":[0.4,0,0.5],"orientation":[0,0,1]}"#).unwrap_err();
    assert!(
        e.to_string()
            .contains("expected an array of 4 quaternion components x, y, z, w"),
        "{e}"
    );
}

#[test]
fn a_seed_of_the_wrong_length_is_refused_naming_it() {
    let e =
        ik(r#"{"position":[0.4,0,0.5],"orientation":[0,0,0,1],"seed":[0,0,0,0,0]}"#).unwrap_err();
    assert_eq!(e.code(), ErrorCode::InvalidArgument);
    assert_eq!(
        e.to_string(),
        "inverse_kinematics: argument \"seed\" = [0,0,0,0,0] is not allowed; expected an array \
         of 6 joint angles [deg]"
    );
}

/// `move_to_pose` needs control (it sends `move_all`); `inverse_kinematics` is open to all.
#[test]
fn move_to_pose_needs_control_and_inverse_kinematics_does_not() {
    use crate::protocol::Definition;
    assert!(MoveToPose::DEF.needs_control());
    assert!(!InverseKinematics::DEF.needs_control());
}
