//! Errors of the TCP client: the MCM's own refusals ([`McmError`]) and what can go wrong on the
//! way ([`Error`]).

use mcm_shared::error_code::ErrorCode;
use mcm_shared::protocol::results::{ErrorOutcome, Generic, ReadError};
use std::time::Duration;

/// How the MCM answered a command it did not do: the result's `outcome`
/// ([`ErrorOutcome`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// The real-time core refused it: nothing changed (`refused`).
    Refused,
    /// Accepted, then failed while running, e.g. a calibration; or it could not be handed to
    /// the real-time core (`failed`).
    Failed,
    /// Sent to the real-time core, but its answer never came or cannot be read: it may or may
    /// not have been executed; read the state (`unknown`). Never "failed".
    OutcomeUnknown,
    /// The gateway refused the line itself: arguments, access rules, unknown command
    /// (`invalid`); also an outcome this version does not know, or an MCM too old to send
    /// one.
    Invalid,
}

impl From<Option<ErrorOutcome>> for ErrorKind {
    fn from(outcome: Option<ErrorOutcome>) -> ErrorKind {
        match outcome {
            Some(ErrorOutcome::Refused) => ErrorKind::Refused,
            Some(ErrorOutcome::Failed) => ErrorKind::Failed,
            Some(ErrorOutcome::Unknown) => ErrorKind::OutcomeUnknown,
            Some(ErrorOutcome::Invalid) | None => ErrorKind::Invalid,
        }
    }
}

/// The MCM's answer to a command it did not do: the command, its `error_code`, the MCM's
/// words and how it ended.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct McmError {
    /// The command it answers (`move_axis`, ...): the result's `command`; the command sent,
    /// from an MCM too old to name it.
    pub command: String,
    /// How the command ended: the result's `outcome`.
    pub kind: ErrorKind,
    /// The MCM's `error_code` (`mcm_shared::error_code`): what a program decides on. `None`
    /// only for a code this version does not know (a newer MCM), or an MCM too old to send
    /// one. A value of a numeric argument outside its range has the code the core gives it
    /// (`unreachable` for a target position, `out_of_range` otherwise), whichever side
    /// refused it.
    pub code: Option<ErrorCode>,
    /// The MCM's `error_message`, unchanged (for people).
    pub message: String,
}

impl McmError {
    /// Read a `generic` ERROR result that answers the command `sent`: its `command`,
    /// `outcome` and `error_code`, never its words.
    pub fn from_generic(sent: &str, g: &Generic) -> McmError {
        McmError {
            command: g.command.as_deref().unwrap_or(sent).to_string(),
            kind: ErrorKind::from(g.outcome()),
            code: g.code(),
            message: g.message().to_string(),
        }
    }
}

/// What a call of the TCP client can end with, other than its result.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The MCM answered the command with an error.
    #[error(transparent)]
    Mcm(#[from] McmError),
    #[error("cannot connect to the MCM at {addr}: {source}")]
    Connect {
        addr: String,
        #[source]
        source: std::io::Error,
    },
    #[error("the connection to the MCM broke during `{command}`: {source}")]
    Io {
        command: String,
        #[source]
        source: std::io::Error,
    },
    /// The MCM closed the connection; `reason` is its last line, if it gave one.
    #[error("the MCM closed the connection{}", reason.as_ref().map(|r| format!(": {r}")).unwrap_or_default())]
    Closed { reason: Option<String> },
    /// An earlier call found the connection broken; call `reconnect()` (or set
    /// `TcpOptions::reconnect_on_next_call`).
    #[error("not connected (the connection broke earlier); call reconnect()")]
    NotConnected,
    /// No result to `command` within `waited`: it may or may not have been executed. The
    /// connection is closed (its result, should it still come, would answer the next call):
    /// the next call fails with [`Error::NotConnected`], or reconnects first with
    /// `TcpOptions::reconnect_on_next_call` (control of the arm is lost with the connection).
    #[error(
        "no result to `{command}` within {waited:?}: it may or may not have been executed; read the state (the connection was closed: reconnect)"
    )]
    Timeout { command: String, waited: Duration },
    /// A line that is not the protocol this client knows (another MCM version?).
    #[error("unexpected line from the MCM while waiting for `{command}` ({problem}): {line}")]
    Protocol {
        command: String,
        problem: ProtocolProblem,
        line: String,
    },
    /// An argument this client refuses before sending anything.
    #[error("{command}: {problem}")]
    Argument { command: String, problem: String },
    /// [`TcpClient::wait_until`](super::TcpClient::wait_until): the condition `what` did not
    /// hold within `waited`; `last` is the last state read.
    #[error(
        "{what}: not reached within {waited:?} (last state: mode {}, positions {:?} deg, velocities {:?} deg/s)",
        last.mode, last.axis_states.position, last.axis_states.velocity
    )]
    NotReached {
        what: String,
        waited: Duration,
        last: Box<super::Status>,
    },
}

/// What is wrong with a line from the MCM ([`Error::Protocol`]).
#[derive(Debug, thiserror::Error)]
pub enum ProtocolProblem {
    #[error("not JSON: {0}")]
    NotJson(#[source] serde_json::Error),
    /// JSON, but no result of this version.
    #[error(transparent)]
    Result(#[from] ReadError),
    /// A result, but not of the type the command answers on success.
    #[error("a {got} result where {expected} was expected")]
    Unexpected {
        got: &'static str,
        expected: &'static str,
    },
}

impl Error {
    /// The MCM's error, if this is one.
    pub fn mcm(&self) -> Option<&McmError> {
        match self {
            Error::Mcm(e) => Some(e),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests;
