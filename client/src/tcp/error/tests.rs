use super::*;
use mcm_shared::command::Axis;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::CommandKind;
use mcm_shared::mode::RejectCode;
use mcm_shared::protocol::Command;
use mcm_shared::protocol::results::{ErrorOutcome, Generic};
use mcm_shared::reply::Reason;
use mcm_shared::reply::{CalibrationFailure, Outcome};

/// The gateway's ERROR result for the core's `outcome` of a `kind` request.
fn core_error(kind: CommandKind, outcome: Outcome) -> Generic {
    Generic::reply_error(kind, &outcome).answering(kind.as_str())
}

/// The gateway's ERROR result for a command line it refuses itself.
fn refusal_of(json: &str) -> Generic {
    let e = Command::from_json(json, &RobotConfig::prob2_default()).unwrap_err();
    Generic::invalid_line(&e)
}

#[test]
fn refusals_failures_and_unknown_outcomes_are_told_apart_with_their_code() {
    let busy = core_error(
        CommandKind::MoveAll,
        Outcome::Refused(Reason::Busy { remaining_s: 0.845 }),
    );
    let e = McmError::from_generic("move_all", &busy);
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Refused, Some(ErrorCode::Busy))
    );
    let failed = core_error(
        CommandKind::Calibrate,
        Outcome::Failed(Reason::CalibrationFailed {
            axis: Axis::new(3).unwrap(),
            cause: CalibrationFailure::NoStop {
                searched_deg: 310.0,
            },
        }),
    );
    let e = McmError::from_generic("calibrate", &failed);
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Failed, Some(ErrorCode::CalibrationFailed))
    );
    let unknown_outcome = Generic::answer_error(
        ErrorOutcome::Unknown,
        ErrorCode::OutcomeUnknown,
        "move_axis: no reply from the real-time core within 5 s: the command may or may not have been executed; check the state",
    );
    let e = McmError::from_generic("move_axis", &unknown_outcome);
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::OutcomeUnknown, Some(ErrorCode::OutcomeUnknown))
    );
    let bad_axis =
        refusal_of(r#"{"command":"move_axis","arguments":{"axis_index":9,"target_position":0}}"#);
    let e = McmError::from_generic("move_axis", &bad_axis);
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Invalid, Some(ErrorCode::OutOfRange)),
        "{bad_axis:?}"
    );
    let unknown = refusal_of(r#"{"command":"move_axis","arguments":{"speed":1}}"#);
    let e = McmError::from_generic("move_axis", &unknown);
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Invalid, Some(ErrorCode::UnknownArgument)),
        "{unknown:?}"
    );
    assert_eq!(e.to_string(), e.message, "the MCM's words, unchanged");
}

/// A program decides on the code, the outcome and the command: words reworded (or in another
/// language) change nothing.
#[test]
fn the_code_outcome_and_command_are_read_not_the_words() {
    let reworded = |g: Generic, words: &str| Generic {
        error_message: Some(words.to_string()),
        ..g
    };
    let refused = core_error(
        CommandKind::MoveAxis,
        Outcome::Refused(Reason::NotOwner { owner: 7 }),
    );
    let e = McmError::from_generic("move_axis", &reworded(refused, "déplacement refusé"));
    assert_eq!(
        (e.command.as_str(), e.kind, e.code),
        ("move_axis", ErrorKind::Refused, Some(ErrorCode::NotOwner))
    );
    let failed = core_error(
        CommandKind::Calibrate,
        Outcome::Failed(Reason::CalibrationFailed {
            axis: Axis::new(3).unwrap(),
            cause: CalibrationFailure::DriveLost,
        }),
    );
    let e = McmError::from_generic("calibrate", &reworded(failed, "move_axis refused: x"));
    assert_eq!(
        (e.command.as_str(), e.kind, e.code),
        (
            "calibrate",
            ErrorKind::Failed,
            Some(ErrorCode::CalibrationFailed)
        )
    );
    // Words that say "refused" make no refusal: without `outcome` (an MCM too old to send
    // it) the kind is `Invalid`, the command the one sent.
    let old = Generic::error(ErrorCode::WrongMode, "move_axis refused: not allowed");
    let e = McmError::from_generic("move_axis", &old);
    assert_eq!(
        (e.command.as_str(), e.kind, e.code),
        ("move_axis", ErrorKind::Invalid, Some(ErrorCode::WrongMode))
    );
}

/// A target out of reach reads the same whichever side refused it: the gateway, parsing it,
/// or the core; either way it is the `unreachable` code, and nothing changed (`outcome` says
/// which side refused it).
#[test]
fn an_unreachable_target_is_read_as_unreachable_from_either_side() {
    let gateway =
        refusal_of(r#"{"command":"move_axis","arguments":{"axis_index":2,"target_position":400}}"#);
    let (min_deg, max_deg) = mcm_shared::ranges::reachable_deg(&RobotConfig::prob2_default(), 1);
    let core = core_error(
        CommandKind::MoveAxis,
        Outcome::Refused(Reason::Unreachable {
            axis: Axis::new(2).unwrap(),
            target_deg: 400.0,
            min_deg,
            max_deg,
        }),
    );
    assert_eq!(
        (gateway.message(), gateway.code()),
        (core.message(), core.code())
    );
    let e = McmError::from_generic("move_axis", &core);
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Refused, Some(ErrorCode::Unreachable)),
        "{core:?}"
    );
    let e = McmError::from_generic("move_axis", &gateway);
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Invalid, Some(ErrorCode::Unreachable)),
        "{gateway:?}"
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
        Reason::InvalidArgument {
            refusal: mcm_shared::ranges::ArgRefusal {
                arg: mcm_shared::ranges::Arg::VelocityFactor,
                axis: None,
                value: 2.0,
                min: 0.001,
                max: 1.0,
            },
        },
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
        Reason::NotIdentifiable {
            condition: 45.0,
            limit: 15.0,
        },
    ];
    for code in RejectCode::ALL.iter().filter(|&&c| c != RejectCode::None) {
        assert!(
            reasons.iter().any(|r| r.code() == *code),
            "reject code {code} has no reason in this test"
        );
    }
    for r in reasons {
        for outcome in [Outcome::Refused(r), Outcome::Failed(r)] {
            let g = core_error(CommandKind::MoveAxis, outcome);
            let e = McmError::from_generic("move_axis", &g);
            assert_eq!(e.code, Some(r.error_code()), "{g:?}");
        }
    }
}
