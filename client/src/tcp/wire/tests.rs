use super::*;
use mcm_shared::command::Axis;
use mcm_shared::mode::{CommandKind, Mode, RejectCode};
use mcm_shared::protocol::results::{Generic, ReadError};
use mcm_shared::reply::{Outcome, Reason, SafetyError};

const STATUS: &str = r#"{"result_type":"status","operating_mode":"HOLD","axis_states":{"time":[1,1,1,1,1,1],"position":[0,1,2,3,4,5],"velocity":[0,0,0,0,0,0],"acceleration":[0,0,0,0,0,0],"current":[0,0,0,0,0,0]}}"#;

#[test]
fn results_are_read_by_result_type() {
    assert!(matches!(
        parse(r#"{"result_type":"generic","error_status":"OK"}"#),
        Ok(Line::Ok)
    ));
    let Ok(Line::Status(s)) = parse(STATUS) else {
        panic!("a status")
    };
    assert_eq!(s.mode, Mode::Hold);
    assert_eq!(s.axis_states.position[5], 5.0);
    assert_eq!(s.detail, None);
    let Ok(Line::Other(Answer::MoveAll(m))) = parse(
        r#"{"result_type":"move_all","velocities":[1,2,3,4,5,6],"longest":3,"max_time_to_target":1.5}"#,
    ) else {
        panic!("move_all")
    };
    assert_eq!(m.longest, 3);
}

/// A line as the gateway writes `g`.
fn line(g: Generic) -> String {
    Answer::Generic(g).to_value().to_string()
}

/// The gateway's ERROR result for the core's refusal of a `kind` request in HOLD.
fn refused_in_hold(kind: CommandKind) -> Generic {
    let outcome = Outcome::Refused(Reason::WrongMode { mode: Mode::Hold });
    Generic::reply_error(kind, &outcome).answering(kind.as_str())
}

#[test]
fn spontaneous_lines_are_events_never_results() {
    let lost = SafetyError {
        seq: 1,
        cycle: 10,
        unix_ns: 0,
        reason: Reason::DriveDisconnected {
            axis: Axis::new(2).unwrap(),
            also: 0,
        },
    };
    let event = Generic::safety_event(&Ok(lost), Mode::Error.to_wire(), "/tmp/x.csv".as_ref());
    let l = parse(&line(event)).unwrap();
    let Line::Event(Event::SafetyError {
        check,
        axis,
        flight_recorder,
        ..
    }) = l
    else {
        panic!("{l:?}")
    };
    assert_eq!(check, Some(RejectCode::DriveDisconnected));
    assert_eq!(axis, Some(2));
    assert_eq!(flight_recorder.as_deref(), Some("/tmp/x.csv"));
    let l = parse(r#"{"result_type":"generic","error_status":"ERROR","error_code":"core_stopping","error_message":"mcm-rt is shutting down: the arm is being stopped"}"#).unwrap();
    assert!(matches!(l, Line::Event(Event::Notice(_))), "{l:?}");
    let l = parse(&line(refused_in_hold(CommandKind::SetTorques))).unwrap();
    let Line::Event(Event::CommandError(e)) = l else {
        panic!("{l:?}")
    };
    assert_eq!(
        (e.command.as_str(), e.code),
        (
            "set_torques",
            Some(mcm_shared::error_code::ErrorCode::WrongMode)
        )
    );
    let cfg = mcm_shared::config::RobotConfig::prob2_default();
    let torques = r#"{"command":"set_torques","arguments":{"torques":[10000,0,0,0,0,0]}}"#;
    let refused = mcm_shared::protocol::Command::from_json(torques, &cfg).unwrap_err();
    let l = parse(&line(Generic::invalid_line(&refused))).unwrap();
    assert!(
        matches!(&l, Line::Event(Event::CommandError(e)) if e.kind == crate::tcp::ErrorKind::Invalid),
        "{l:?}"
    );
    let l = parse(&line(refused_in_hold(CommandKind::MoveAxis))).unwrap();
    assert!(matches!(l, Line::Error(_)), "{l:?}");
}

/// The refusal of a command that answers nothing on success is told by its `command`, never
/// by its words.
#[test]
fn a_refusal_without_a_result_is_known_by_its_command_not_its_words() {
    let reworded = Generic {
        error_message: Some("Drehmomente abgelehnt".into()),
        ..refused_in_hold(CommandKind::SetVelocities)
    };
    let l = parse(&line(reworded)).unwrap();
    let Line::Event(Event::CommandError(e)) = l else {
        panic!("{l:?}")
    };
    assert_eq!(
        (e.command.as_str(), e.kind),
        ("set_velocities", crate::tcp::ErrorKind::Refused)
    );
    // Words that start with the command's name name no command.
    let unnamed = Generic {
        command: None,
        ..refused_in_hold(CommandKind::SetTorques)
    };
    assert!(unnamed.message().starts_with("set_torques refused"));
    let l = parse(&line(unnamed)).unwrap();
    assert!(matches!(l, Line::Error(_)), "{l:?}");
}

#[test]
fn bad_lines_say_what_is_wrong() {
    let e = parse("hello").unwrap_err();
    assert!(matches!(e, ProtocolProblem::NotJson(_)), "{e:?}");
    assert!(e.to_string().starts_with("not JSON"), "{e}");
    let e = parse("{}").unwrap_err();
    assert!(
        matches!(e, ProtocolProblem::Result(ReadError::NoResultType)),
        "{e:?}"
    );
    assert_eq!(e.to_string(), "no result_type");
    let e = parse(&STATUS.replace("HOLD", "FLYING")).unwrap_err();
    assert!(e.to_string().contains("FLYING"), "{e}");
}
