//! `hold`: enter HOLD: the axes keep their positions; from OFF or ERROR it clears the error
//! and powers the drives. Open to every client (a stop is never refused for lack of control);
//! answers the status after the mode change.

use super::prelude::*;

/// `hold` (no arguments).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Hold;

impl Definition for Hold {
    const DEF: CommandDef = CommandDef {
        name: "hold",
        kind: Some(CommandKind::Hold),
        sends: None,
        success: Success::Status,
        group: Group::EveryMode,
        ok_words: "",
        summary: "enter HOLD: axes keep their positions; clears errors and powers the drives",
        args: &[],
        modes: "every mode",
        how: "",
        reply: "the status table after the mode change",
        examples: &["hold"],
        notes: "From OFF or ERROR it clears the error and re-enables power; it fails with the \
                reason while the cause persists (e.g. the emergency stop is still pressed).",
    };

    fn parse(_: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        Ok(Hold)
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::Hold]
    }
}
