//! Result lines as the transports write them (JSON values), all built from the typed results of
//! [`mcm_shared::protocol::results`]: the contract's one encoding. The HMI renders the typed
//! results themselves.

use crate::core_link::bridge::SafetyEvent;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::protocol::CommandError;
use mcm_shared::protocol::results::{Answer, ErrorOutcome, Generic, Status};
use mcm_shared::sample::StateSample;
use serde_json::Value;

/// A generic ERROR result with its code and words.
pub fn error(code: ErrorCode, message: impl Into<String>) -> Value {
    Answer::error(code, message).to_value()
}

/// A generic ERROR result answering a request that ended as `outcome`.
pub fn answer_error(outcome: ErrorOutcome, code: ErrorCode, message: impl Into<String>) -> Value {
    Answer::answer_error(outcome, code, message).to_value()
}

/// The ERROR of a line refused before it became a command (outcome `invalid`).
pub fn invalid_line(e: &CommandError) -> Value {
    Answer::Generic(Generic::invalid_line(e)).to_value()
}

/// The status of `state` as the result of `command` (`status`, or a command answered with the
/// status of its cycle: `hold`, `release`, ...); an ERROR naming `command` when the state is
/// from another MCM version (outcome `unknown`: the command was done, its state cannot be
/// read).
pub fn status_answer(command: &str, state: &StateSample, detail: bool) -> Answer {
    match Status::from_state(state, detail) {
        Ok(s) => Answer::Status(Box::new(s)),
        Err(e) => Answer::answer_error(
            ErrorOutcome::Unknown,
            ErrorCode::VersionMismatch,
            format!("{command}: {e}"),
        ),
    }
}

/// A spontaneous status result of `state` (a control mode's session, the ZeroMQ `state`
/// topic); an ERROR that answers no command when the state is from another MCM version.
pub fn status(state: &StateSample, detail: bool) -> Value {
    match Status::from_state(state, detail) {
        Ok(s) => Answer::Status(Box::new(s)).to_value(),
        Err(e) => error(ErrorCode::VersionMismatch, format!("status: {e}")),
    }
}

/// The spontaneous ERROR sent to every client when a safety check trips: the check, the axis,
/// the values, the mode it left the robot in, and the flight-recorder file.
pub fn safety_generic(ev: &SafetyEvent) -> Generic {
    Generic::safety_event(&ev.error, ev.mode, &ev.file)
}

/// [`safety_generic`] as a result line.
pub fn safety_event(ev: &SafetyEvent) -> Value {
    Answer::Generic(safety_generic(ev)).to_value()
}
