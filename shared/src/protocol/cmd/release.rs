//! `release`: enter RELEASE (from HOLD, every axis calibrated): the arm can be moved by
//! hand, gravity and friction compensated. Answers the status after the mode change.

use super::prelude::*;

/// `release` (no arguments).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Release;

impl Definition for Release {
    const DEF: CommandDef = CommandDef {
        name: "release",
        kind: Some(CommandKind::Release),
        sends: None,
        success: Success::Status,
        group: Group::ModeChange,
        ok_words: "",
        summary: "enter RELEASE: move the arm by hand (gravity and friction compensated)",
        args: &[],
        modes: IN_HOLD,
        how: TO_HOLD,
        reply: "the status table after the mode change",
        examples: &["release"],
        notes: "In RELEASE only `hold` and `status` (and `info`, `sleep`) are accepted.",
    };

    fn parse(_: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        Ok(Release)
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::Release]
    }
}
