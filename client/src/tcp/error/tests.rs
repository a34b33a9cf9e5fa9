use super::*;
use mcm_shared::command::Axis;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::CommandKind;
use mcm_shared::protocol::Command;
use mcm_shared::protocol::results::Generic;
use mcm_shared::reply::{CalibrationFailure, Outcome};

/// The gateway's words for the core's `outcome` of a `kind` request.
fn core_words(kind: CommandKind, outcome: Outcome) -> String {
    Generic::reply_error(kind, &outcome).message().to_string()
}

/// The gateway's words for a command line it refuses itself.
fn refusal_of(json: &str) -> String {
    Command::from_json(json, &RobotConfig::prob2_default())
        .unwrap_err()
        .to_string()
}

#[test]
fn refusals_failures_and_unknown_outcomes_are_told_apart_with_their_code() {
    let busy = core_words(
        CommandKind::MoveAll,
        Outcome::Refused(Reason::Busy { remaining_s: 0.845 }),
    );
    let e = McmError::from_message("move_all", &busy);
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Refused, Some(RejectCode::Busy))
    );
    let failed = core_words(
        CommandKind::Calibrate,
        Outcome::Failed(Reason::CalibrationFailed {
            axis: Axis::new(3).unwrap(),
            cause: CalibrationFailure::NoStop {
                searched_deg: 310.0,
            },
        }),
    );
    let e = McmError::from_message("calibrate", &failed);
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Failed, Some(RejectCode::CalibrationFailed))
    );
    // The gateway's words when the core's reply does not come (gateway/src/command.rs,
    // `bridge_message`, pinned by its own test).
    let e = McmError::from_message(
        "move_axis",
        "move_axis: no reply from the real-time core within 5 s: the command may or may not have been executed; check the state",
    );
    assert_eq!((e.kind, e.code), (ErrorKind::OutcomeUnknown, None));
    let bad_axis =
        refusal_of(r#"{"command":"move_axis","arguments":{"axis_index":9,"target_position":0}}"#);
    let e = McmError::from_message("move_axis", &bad_axis);
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Invalid, Some(RejectCode::OutOfRange)),
        "{bad_axis}"
    );
    let unknown = refusal_of(r#"{"command":"move_axis","arguments":{"speed":1}}"#);
    let e = McmError::from_message("move_axis", &unknown);
    assert_eq!((e.kind, e.code), (ErrorKind::Invalid, None), "{unknown}");
    // The gateway's own words for a refusal to a client that does not control the arm
    // (gateway/src/command/access/mod.rs, `reply_error`).
    let e = McmError::from_message(
        "move_axis",
        "move_axis refused: the arm is controlled by JSON client 10.1.2.3:51234 (client id 0x1a2b00000003); only `hold`, `status` and `info` are open to others until it sends `release_control` or disconnects",
    );
    assert_eq!(e.code, Some(RejectCode::NotOwner));
    assert_eq!(e.to_string(), e.message, "the MCM's words, unchanged");
}

/// A target out of reach reads the same whichever side refused it: the gateway, parsing it,
/// or the core; either way it is the `unreachable` code.
#[test]
fn an_unreachable_target_is_read_as_unreachable_from_either_side() {
    let gateway =
        refusal_of(r#"{"command":"move_axis","arguments":{"axis_index":2,"target_position":400}}"#);
    let (min_deg, max_deg) = mcm_shared::ranges::reachable_deg(&RobotConfig::prob2_default(), 1);
    let core = core_words(
        CommandKind::MoveAxis,
        Outcome::Refused(Reason::Unreachable {
            axis: Axis::new(2).unwrap(),
            target_deg: 400.0,
            min_deg,
            max_deg,
        }),
    );
    assert_eq!(gateway, core);
    let e = McmError::from_message("move_axis", &core);
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Invalid, Some(RejectCode::Unreachable)),
        "{core}"
    );
}

#[test]
fn every_reason_of_the_core_is_read_back_to_its_code() {
    use mcm_shared::mode::Mode;
    use mcm_shared::reply::PvtQuantity;
    let a = Axis::new(2).unwrap();
    let reasons = [
        Reason::WrongMode { mode: Mode::Hold },
        Reason::NotCalibrated { axis: a },
        Reason::EmergencyStop,
        Reason::DriveDisconnected { axis: a, also: 0 },
        Reason::DriveDisconnected {
            axis: a,
            also: 0b1_0001,
        },
        Reason::InvalidArgument(mcm_shared::ranges::ArgRefusal {
            arg: mcm_shared::ranges::Arg::VelocityFactor,
            axis: None,
            value: 2.0,
            min: 0.001,
            max: 1.0,
        }),
        Reason::DriveFault {
            axis: Some(a),
            code: 0x2310,
        },
        Reason::OutOfRange {
            axis: None,
            value: 2.0,
            min: 0.0,
            max: 1.0,
        },
        Reason::NotAvailable,
        Reason::NotSimulated,
        Reason::QueueFull {
            offered: 3,
            free: 1,
        },
        Reason::PositionLimit {
            axis: a,
            position_deg: 1.0,
            limit_deg: 0.5,
        },
        Reason::VelocityLimit {
            axis: a,
            velocity_deg_s: 1.0,
            limit_deg_s: 0.5,
        },
        Reason::BrakingDistance {
            axis: a,
            stop_deg: 1.0,
            limit_deg: 0.5,
        },
        Reason::FollowingError {
            axis: a,
            error_deg: 1.0,
            band_deg: 0.5,
        },
        Reason::Overload {
            axis: a,
            current_a: 4.0,
            limit_a: 4.0,
        },
        Reason::CalibrationFailed {
            axis: a,
            cause: CalibrationFailure::DriveLost,
        },
        Reason::Aborted,
        Reason::Busy { remaining_s: 1.0 },
        Reason::PvtPoint {
            axis: a,
            point: 2,
            quantity: PvtQuantity::Velocity,
            value: 1.0,
            limit: 0.5,
        },
        Reason::Unreachable {
            axis: a,
            target_deg: 1.0,
            min_deg: 0.0,
            max_deg: 0.5,
        },
        Reason::NotOwner { owner: 7 },
        Reason::ShuttingDown,
    ];
    for code in RejectCode::ALL.iter().filter(|&&c| c != RejectCode::None) {
        assert!(
            reasons.iter().any(|r| r.code() == *code),
            "reject code {code} has no reason in this test"
        );
    }
    for r in reasons {
        for outcome in [Outcome::Refused(r), Outcome::Failed(r)] {
            let words = core_words(CommandKind::MoveAxis, outcome);
            let e = McmError::from_message("move_axis", &words);
            assert_eq!(e.code, Some(r.code()), "{words}");
        }
    }
}
