//! Result lines as the transports write them (JSON values), all built from the typed results of
//! [`mcm_shared::protocol::results`]: the contract's one encoding. The HMI renders the typed
//! results themselves.

use crate::core_link::bridge::SafetyEvent;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::protocol::results::{Answer, Generic, Status};
use mcm_shared::sample::StateSample;
use serde_json::Value;

/// A generic ERROR result with its code and words.
pub fn error(code: ErrorCode, message: impl Into<String>) -> Value {
    Answer::error(code, message).to_value()
}

/// The status of `state` as the result of `command` (`status`, or a command answered with the
/// status of its cycle: `hold`, `release`, ...); an ERROR naming `command` when the state is
/// from another MCM version.
pub fn status_answer(command: &str, state: &StateSample, detail: bool) -> Answer {
    match Status::from_state(state, detail) {
        Ok(s) => Answer::Status(Box::new(s)),
        Err(e) => Answer::error(ErrorCode::VersionMismatch, format!("{command}: {e}")),
    }
}

/// A spontaneous status result of `state` (a control mode's session, the ZeroMQ `state`
/// topic).
pub fn status(state: &StateSample, detail: bool) -> Value {
    status_answer("status", state, detail).to_value()
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
