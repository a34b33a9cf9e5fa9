//! `status`: the mode and every axis's state (the `status` result,
//! [`crate::protocol::results::Status`]); `"detail": true` adds the hardware status and the
//! per-axis, timing and access detail. Answered from the newest state, without waiting for a
//! cycle.

use super::prelude::*;

/// `status`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Status {
    pub detail: bool,
}

impl Definition for Status {
    const DEF: CommandDef = CommandDef {
        name: "status",
        kind: Some(CommandKind::Status),
        sends: None,
        success: Success::Status,
        group: Group::EveryMode,
        ok_words: "",
        summary: "the mode and every axis's position, velocity and current",
        args: &[arg(
            "detail",
            "",
            Kind::Bool,
            true,
            "false",
            "add commanded and measured position, following error, i2t, calibration, drives and cycle timing",
        )],
        modes: "every mode",
        how: "",
        reply: "the status table",
        examples: &["status", "status detail"],
        notes: "`watch` shows the same table, refreshed until a key is pressed.",
    };

    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        Ok(Status {
            detail: args.boolean("detail")?.unwrap_or(false),
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        if self.detail {
            m.insert("detail".into(), true.into());
        }
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::Status]
    }
}
