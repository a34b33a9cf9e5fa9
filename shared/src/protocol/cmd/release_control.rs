//! `release_control`: give up control of the arm's motion. What this connection drove (a
//! move, a PVT stream, RELEASE, TORQUE_CONTROL, a calibration) ends in HOLD with the
//! controlled stop. OK when nobody controls the arm; refused (`not_owner`) when another
//! client does. No arguments.

use super::prelude::*;

/// `release_control` (no arguments).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ReleaseControl;

impl Definition for ReleaseControl {
    const DEF: CommandDef = CommandDef {
        name: "release_control",
        kind: Some(CommandKind::ReleaseControl),
        sends: None,
        success: Success::Ok,
        group: Group::Control,
        ok_words: "",
        summary: "give up control of the arm's motion (what this session drove stops in HOLD)",
        args: &[],
        modes: "every mode",
        how: "",
        reply: "OK (also when nobody controls the arm)",
        examples: &["release_control"],
        notes: "A move, PVT stream, RELEASE, TORQUE_CONTROL or calibration of this session \
                ends with the controlled stop to HOLD.",
    };

    fn parse(_: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        Ok(ReleaseControl)
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::ReleaseControl]
    }
}
