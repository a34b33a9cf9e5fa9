//! Lines of the JSON protocol: the parsing of result lines by `result_type`, and telling the
//! result of a command from spontaneous messages.

use super::error::McmError;
use super::types::{Event, Status};
use mcm_shared::protocol::results::Answer;
use mcm_shared::protocol::{self, Success};
use serde_json::Value;

/// Beginnings of the spontaneous notices about the MCM's life and this connection
/// (`docs/protocol.md`, "Shutdown notices" and "Connections"): they answer no command.
const NOTICES: &[&str] = &[
    "mcm-rt is shutting down",
    "mcm-rt stopped",
    "the MCM is shutting down",
    "idle timeout:",
    "line timeout:",
    "connection closed",
    "connection refused",
    "the client took no result line",
];

/// Whether `command` answers nothing on success (its refusals come later, as events).
pub(crate) fn answers_nothing(command: &str) -> bool {
    protocol::find(command).is_some_and(|d| d.success == Success::Nothing)
}

/// One line the MCM sent, read.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Line {
    /// `generic` OK.
    Ok,
    /// `generic` ERROR that may answer a command: its words.
    Error(String),
    Status(Box<Status>),
    /// Another result (`initialization`, `move_all`, `sim`).
    Other(Answer),
    /// Spontaneous: never the answer to a command.
    Event(Event),
}

/// Read one line. `Err` names what is wrong with it.
pub(crate) fn parse(line: &str) -> Result<Line, String> {
    let v: Value = serde_json::from_str(line).map_err(|e| format!("not JSON: {e}"))?;
    let g = match Answer::from_value(&v)? {
        Answer::Generic(g) => g,
        Answer::Status(s) => return Ok(Line::Status(s)),
        other => return Ok(Line::Other(other)),
    };
    if g.is_ok() {
        return Ok(Line::Ok);
    }
    let message = g.message().to_string();
    if g.check.is_some() {
        return Ok(Line::Event(Event::SafetyError {
            check: g.check_code(),
            axis: g.axis,
            message,
            flight_recorder: g.flight_recorder,
        }));
    }
    if message.starts_with("safety check tripped")
        || message.contains("safety errors were not delivered")
    {
        return Ok(Line::Event(Event::SafetyError {
            check: None,
            axis: None,
            message,
            flight_recorder: None,
        }));
    }
    if NOTICES.iter().any(|n| message.starts_with(n)) {
        return Ok(Line::Event(Event::Notice(message)));
    }
    let command = message.split([' ', ':']).next().unwrap_or_default();
    if answers_nothing(command) {
        // No result on success: a refusal is an event.
        return Ok(Line::Event(Event::CommandError(McmError::from_message(
            command, &message,
        ))));
    }
    Ok(Line::Error(message))
}

#[cfg(test)]
mod tests {
    use super::*;
    use mcm_shared::mode::{Mode, RejectCode};

    const STATUS: &str = r#"{"result_type":"status","operating_mode":"HOLD","axis_states":{"time":[1,1,1,1,1,1],"position":[0,1,2,3,4,5],"velocity":[0,0,0,0,0,0],"acceleration":[0,0,0,0,0,0],"current":[0,0,0,0,0,0]}}"#;

    #[test]
    fn results_are_read_by_result_type() {
        assert_eq!(
            parse(r#"{"result_type":"generic","error_status":"OK"}"#),
            Ok(Line::Ok)
        );
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

    #[test]
    fn spontaneous_lines_are_events_never_results() {
        let l = parse(r#"{"result_type":"generic","error_status":"ERROR","error_message":"safety check tripped: the drive of axis 2 does not answer on the bus; mode is now ERROR; flight recorder: /tmp/x.csv","check":"drive_disconnected","axis":2,"flight_recorder":"/tmp/x.csv"}"#).unwrap();
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
        let l = parse(r#"{"result_type":"generic","error_status":"ERROR","error_message":"mcm-rt is shutting down: the arm is being stopped"}"#).unwrap();
        assert!(matches!(l, Line::Event(Event::Notice(_))), "{l:?}");
        let l = parse(r#"{"result_type":"generic","error_status":"ERROR","error_message":"set_torques refused: not allowed in mode HOLD"}"#).unwrap();
        let Line::Event(Event::CommandError(e)) = l else {
            panic!("{l:?}")
        };
        assert_eq!(
            (e.command.as_str(), e.code),
            ("set_torques", Some(RejectCode::WrongMode))
        );
        let l = parse(r#"{"result_type":"generic","error_status":"ERROR","error_message":"set_torques: argument \"torques[0]\" = 10000.0 is not allowed"}"#).unwrap();
        assert!(
            matches!(&l, Line::Event(Event::CommandError(e)) if e.kind == crate::tcp::ErrorKind::Invalid),
            "{l:?}"
        );
        let l = parse(r#"{"result_type":"generic","error_status":"ERROR","error_message":"move_axis refused: not allowed in mode HOLD"}"#).unwrap();
        assert!(matches!(l, Line::Error(_)), "{l:?}");
    }

    #[test]
    fn bad_lines_say_what_is_wrong() {
        assert!(parse("hello").unwrap_err().starts_with("not JSON"));
        assert_eq!(parse("{}").unwrap_err(), "no result_type");
        let e = parse(&STATUS.replace("HOLD", "FLYING")).unwrap_err();
        assert!(e.contains("FLYING"), "{e}");
    }
}
