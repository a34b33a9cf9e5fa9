//! Errors of the shared-memory client.

use mcm_shared::command::DecodeError;
use mcm_shared::mode::CommandKind;
use mcm_shared::reply::Reason;
use std::time::Duration;

/// What a call of the shared-memory client can end with, other than its result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShmError {
    #[error(transparent)]
    InstanceName(#[from] mcm_shared::service::InvalidInstanceName),
    /// The MCM of this instance is not running (its services do not exist).
    #[error(
        "the MCM instance {instance:?} is not running on this computer (service `{service}` does not exist); start it (`cargo run --release -- --instance {instance}`) or check the instance name"
    )]
    NotRunning { instance: String, service: String },
    /// The core's service is of another MCM version than this client.
    #[error(
        "service `{service}` of the running MCM does not match this client: {problem}; build the client from the same MCM version as the running core (iceoryx2 =0.10.0, {expected})"
    )]
    Incompatible {
        service: String,
        problem: String,
        /// The sample type this client expects (type name, size).
        expected: String,
    },
    /// An iceoryx2 step failed for another reason.
    #[error("{step} failed: {problem}")]
    Ipc { step: String, problem: String },
    /// No new state within the wait: the core stopped publishing (or was never started).
    #[error(
        "no new state from the MCM within {waited:?} (last cycle seen: {last_seq}); the real-time core is not publishing"
    )]
    Timeout { waited: Duration, last_seq: u64 },
    /// The core refused the command (nothing changed); `reason` gives the MCM's words.
    #[error("{command} refused: {reason}")]
    Refused {
        command: CommandKind,
        reason: Reason,
    },
    /// The core accepted the command, then it failed while running.
    #[error("{command} failed: {reason}")]
    Failed {
        command: CommandKind,
        reason: Reason,
    },
    /// No reply came: the command may or may not have been executed; read the state. Never
    /// "failed".
    #[error(
        "{command}: no reply from the real-time core within {waited:?}{}: the command may or may not have been executed; check the state",
        if *overwritten { " (replies were overwritten before this client read them: it fell more than 8192 replies behind)" } else { "" }
    )]
    OutcomeUnknown {
        command: CommandKind,
        waited: Duration,
        overwritten: bool,
    },
    /// The reply does not decode: the core is of another MCM version.
    #[error(
        "{command}: the reply of the real-time core does not read ({error}); build the client from the same MCM version as the core"
    )]
    Undecodable {
        command: CommandKind,
        error: DecodeError,
    },
    /// An argument this client refuses before sending anything.
    #[error("{command}: {problem}")]
    Argument {
        command: CommandKind,
        problem: String,
    },
    /// [`ShmClient::wait_until`](super::ShmClient::wait_until): the condition `what` held for
    /// no state within `waited`.
    #[error("{what}: not reached within {waited:?} (last cycle read: {last_seq})")]
    NotReached {
        what: String,
        waited: Duration,
        last_seq: u64,
    },
}

impl ShmError {
    /// The MCM's reason, for a refusal or a failure.
    pub fn reason(&self) -> Option<&Reason> {
        match self {
            ShmError::Refused { reason, .. } | ShmError::Failed { reason, .. } => Some(reason),
            _ => None,
        }
    }
}
