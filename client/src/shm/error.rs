//! What the shared-memory client's calls can end with besides their result: one error per
//! operation. Opening ([`OpenError`](super::OpenError)) and publishing
//! ([`SendError`](super::SendError)) are the ports' own ([`super::ports`]); waiting for a state,
//! a command waiting for its reply and waiting for a condition are here. Each keeps iceoryx2's
//! own error as its source.

use super::ports::SendError;
use iceoryx2::port::listener::ListenerWaitError;
use mcm_shared::command::DecodeError;
use mcm_shared::mode::CommandKind;
use mcm_shared::reply::{Outcome, Reason};
use std::time::Duration;

/// Waiting for the next state failed ([`ShmClient::wait_state`](super::ShmClient::wait_state)).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WaitError {
    /// No new state within the wait: the core stopped publishing (or was never started).
    #[error(
        "no new state from the MCM within {waited:?} (last cycle seen: {last_seq}); the real-time core is not publishing"
    )]
    Timeout { waited: Duration, last_seq: u64 },
    /// iceoryx2's listener of the state event failed.
    #[error("waiting on `{service}` failed: {source}")]
    Listener {
        service: String,
        #[source]
        source: ListenerWaitError,
    },
}

/// A command that waits for its reply did not end with `Done`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RequestError {
    /// The command could not be published (nothing was sent).
    #[error(transparent)]
    Send(#[from] SendError),
    /// Waiting for the reply failed in iceoryx2's listener (a reply that does not come in time
    /// is [`RequestError::OutcomeUnknown`]).
    #[error(transparent)]
    Wait(#[from] WaitError),
    /// The core refused the command (nothing changed); `reason` gives the MCM's words (a
    /// value of an argument outside its range in the gateway's words for it).
    #[error("{}", Outcome::Refused(*reason).words(*command))]
    Refused {
        command: CommandKind,
        reason: Reason,
    },
    /// The core accepted the command, then it failed while running.
    #[error("{}", Outcome::Failed(*reason).words(*command))]
    Failed {
        command: CommandKind,
        reason: Reason,
    },
    /// No reply came: the command may or may not have been executed; read the state. Never
    /// "failed".
    #[error(
        "{command}: no reply from the real-time core within {waited:?}{}: the command may or may not have been executed; check the state",
        if *overwritten { format!(" (replies were overwritten before this client read them: it fell more than {} replies behind)", super::replies::KEPT) } else { String::new() }
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
        #[source]
        error: DecodeError,
    },
    /// An argument this client refuses before sending anything.
    #[error("{command}: {problem}")]
    Argument {
        command: CommandKind,
        problem: String,
    },
}

impl RequestError {
    /// The MCM's reason, for a refusal or a failure.
    pub fn reason(&self) -> Option<&Reason> {
        match self {
            RequestError::Refused { reason, .. } | RequestError::Failed { reason, .. } => {
                Some(reason)
            }
            _ => None,
        }
    }
}

/// [`ShmClient::wait_until`](super::ShmClient::wait_until) ended without its condition.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WaitUntilError {
    /// No state came, or the listener failed.
    #[error(transparent)]
    Wait(#[from] WaitError),
    /// The condition `what` held for no state within `waited`.
    #[error("{what}: not reached within {waited:?} (last cycle read: {last_seq})")]
    NotReached {
        what: String,
        waited: Duration,
        last_seq: u64,
    },
}
