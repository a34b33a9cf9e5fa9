//! The `outcome` of an ERROR result that answers a command: how the command ended. The same
//! reason can end a command either way (a `following_error` refuses a move, or ends a
//! calibration that ran), so a client reads this field, never the words, to know whether
//! anything changed.

use core::fmt;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// How a command ended that the MCM did not do (`outcome` of its ERROR result; spontaneous
/// errors have none).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ErrorOutcome {
    /// The real-time core refused it: nothing changed.
    Refused,
    /// Accepted, then failed while running (e.g. a calibration that found no reference), or it
    /// could not be handed to the real-time core (`core_unavailable`, `shutting_down`).
    Failed,
    /// The gateway refused the line itself (not a command, its arguments, the access rules):
    /// nothing changed.
    Invalid,
    /// Sent to the real-time core, but its answer never came or cannot be read: it may or may
    /// not have been executed; read the state.
    Unknown,
}

impl ErrorOutcome {
    /// Every outcome.
    pub const ALL: [ErrorOutcome; 4] = [
        ErrorOutcome::Refused,
        ErrorOutcome::Failed,
        ErrorOutcome::Invalid,
        ErrorOutcome::Unknown,
    ];

    /// The name on the wire (`outcome`).
    pub const fn as_str(self) -> &'static str {
        match self {
            ErrorOutcome::Refused => "refused",
            ErrorOutcome::Failed => "failed",
            ErrorOutcome::Invalid => "invalid",
            ErrorOutcome::Unknown => "unknown",
        }
    }

    /// What it means, for people (one sentence).
    pub const fn meaning(self) -> &'static str {
        match self {
            ErrorOutcome::Refused => "The real-time core refused the command: nothing changed.",
            ErrorOutcome::Failed => {
                "The command was accepted, then failed while running (e.g. a calibration), or it \
                 could not be handed to the real-time core (`core_unavailable`, `shutting_down`)."
            }
            ErrorOutcome::Invalid => {
                "The gateway refused the line itself (not a command, its arguments, the access \
                 rules): nothing changed."
            }
            ErrorOutcome::Unknown => {
                "The command was sent to the real-time core, but its answer never came or cannot \
                 be read: it may or may not have been executed; read the state."
            }
        }
    }

    /// The outcome called `name` (as [`ErrorOutcome::as_str`] writes it).
    pub fn from_name(name: &str) -> Option<ErrorOutcome> {
        ErrorOutcome::ALL.into_iter().find(|o| o.as_str() == name)
    }

    /// Read an `outcome` field: one this version does not know (a newer MCM) reads as `None`,
    /// so that its result still reads.
    pub(crate) fn read<'de, D: Deserializer<'de>>(d: D) -> Result<Option<ErrorOutcome>, D::Error> {
        let name = Option::<String>::deserialize(d)?;
        Ok(name.as_deref().and_then(ErrorOutcome::from_name))
    }
}

impl Serialize for ErrorOutcome {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

impl fmt::Display for ErrorOutcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}
