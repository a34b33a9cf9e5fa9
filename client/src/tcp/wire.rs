//! Lines of the JSON protocol: the parsing of result lines by `result_type`, and telling the
//! result of a command from spontaneous messages.

use super::error::{McmError, ProtocolProblem};
use super::types::{Event, Status};
use mcm_shared::error_code::ErrorCode;
use mcm_shared::protocol::results::{Answer, Generic};
use mcm_shared::protocol::{self, Success};
use serde_json::Value;

/// Whether `command` answers nothing on success (its refusals come later, as events).
pub(crate) fn answers_nothing(command: &str) -> bool {
    protocol::find(command).is_some_and(|d| d.success == Success::Nothing)
}

/// One line the MCM sent, read.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Line {
    /// `generic` OK.
    Ok,
    /// `generic` ERROR that may answer a command.
    Error(Generic),
    Status(Box<Status>),
    /// Another result (`initialization`, `move_all`, `sim`).
    Other(Answer),
    /// Spontaneous: never the answer to a command.
    Event(Event),
}

/// Read one line. `Err` names what is wrong with it.
pub(crate) fn parse(line: &str) -> Result<Line, ProtocolProblem> {
    let v: Value = serde_json::from_str(line).map_err(ProtocolProblem::NotJson)?;
    let g = match Answer::from_value(&v)? {
        Answer::Generic(g) => g,
        Answer::Status(s) => return Ok(Line::Status(s)),
        other => return Ok(Line::Other(other)),
    };
    if g.is_ok() {
        return Ok(Line::Ok);
    }
    let message = g.message().to_string();
    // A spontaneous safety error names its check and always its flight-recorder file (also
    // one whose record this version cannot read: no check then).
    if g.check.is_some() || g.flight_recorder.is_some() {
        return Ok(Line::Event(Event::SafetyError {
            check: g.check_code(),
            axis: g.axis,
            message,
            flight_recorder: g.flight_recorder,
        }));
    }
    let code = g.code();
    if code == Some(ErrorCode::EventsLost) {
        return Ok(Line::Event(Event::SafetyError {
            check: None,
            axis: None,
            message,
            flight_recorder: None,
        }));
    }
    if code.is_some_and(ErrorCode::is_spontaneous) {
        return Ok(Line::Event(Event::Notice(message)));
    }
    if let Some(command) = g.command.as_deref().filter(|c| answers_nothing(c)) {
        // No result on success: a refusal is an event.
        return Ok(Line::Event(Event::CommandError(McmError::from_generic(
            command, &g,
        ))));
    }
    Ok(Line::Error(g))
}

#[cfg(test)]
mod tests;
