//! `take_control`: make this connection the one that controls the arm's motion. Refused
//! (`not_owner`, naming the owner) while another client controls it; OK when this connection
//! already does. Subject to the gateway's access rules: allowed network, and the shared secret
//! when one is configured. No arguments.

use super::prelude::*;

/// `take_control` (no arguments).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TakeControl;

impl Definition for TakeControl {
    const DEF: CommandDef = CommandDef {
        name: "take_control",
        kind: Some(CommandKind::TakeControl),
        sends: None,
        success: Success::Ok,
        group: Group::Control,
        ok_words: "",
        summary: "make this session the one that controls the arm's motion",
        args: &[],
        modes: "every mode",
        how: "",
        reply: "OK, or who controls the arm when another client does",
        examples: &["take_control"],
        notes: "Only one client (JSON, HMI or shared memory) controls the arm at a time; the \
                first motion command of a client takes control implicitly when nobody has it. \
                Others may read the state and always `hold`. Control ends with \
                `release_control` or when the session closes: what it drove stops in HOLD. \
                Needs an allowed network and, when configured, `authenticate` first.",
    };

    fn parse(_: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        Ok(TakeControl)
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::TakeControl]
    }
}
