//! Lines of the JSON protocol: the parsing of result lines by `result_type`, and telling the
//! result of a command from spontaneous messages.

use super::error::{McmError, ProtocolProblem};
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
mod tests;
