//! `info`: robot, version, cycle time and the limits of every axis (the `initialization`
//! result, [`crate::protocol::results::Initialization`]).

use super::prelude::*;

/// `info` (no arguments).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Info;

impl Definition for Info {
    const DEF: CommandDef = CommandDef {
        name: "info",
        kind: Some(CommandKind::Info),
        sends: None,
        success: Success::Initialization,
        group: Group::EveryMode,
        ok_words: "",
        summary: "robot, version, cycle time and the limits of every axis",
        args: &[],
        modes: "every mode",
        how: "",
        reply: "a table of the axis limits",
        examples: &["info"],
        notes: "",
    };

    fn parse(_: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        Ok(Info)
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::Info]
    }
}
