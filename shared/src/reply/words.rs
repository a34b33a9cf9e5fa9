//! The one wording of the core's answers for people, used by every interface (the gateway's
//! results, the shared-memory client's errors and its control loop): a refused or failed
//! request prefixed with its command, a value of an argument outside its range worded as the
//! gateway words its own refusal of it, and a safety trip. Formatting: not used inside the
//! real-time cycle.

use super::{Outcome, SafetyError};
use crate::mode::CommandKind;
use core::fmt;

/// The words for the `outcome` of a `kind` request ([`Outcome::words`]): `move_all refused:
/// ...`, `calibrate failed: ...`, `move_axis: argument "target_position" = 400 is not
/// allowed; expected ...` (a value of an argument outside its range, whichever side refused
/// it), `hold done`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutcomeWords {
    pub kind: CommandKind,
    pub outcome: Outcome,
}

impl Outcome {
    /// Its words for a request of `kind`.
    pub fn words(self, kind: CommandKind) -> OutcomeWords {
        OutcomeWords {
            kind,
            outcome: self,
        }
    }
}

impl fmt::Display for OutcomeWords {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = self.kind;
        match self.outcome {
            Outcome::Refused(reason) => match reason.argument(kind) {
                Some(arg) => write!(f, "{kind}: {arg}"),
                None => write!(f, "{kind} refused: {reason}"),
            },
            Outcome::Failed(reason) => write!(f, "{kind} failed: {reason}"),
            Outcome::Done(_) => write!(f, "{kind} done"),
        }
    }
}

/// `safety check tripped: ` and the reason.
impl fmt::Display for SafetyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "safety check tripped: {}", self.reason)
    }
}

#[cfg(test)]
mod tests;
