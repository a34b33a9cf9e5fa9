//! `identify_payload`: the load on the flange, estimated by the real-time core from the joint
//! torques the drives hold at a few wrist and elbow poses; the arm moves through them and back.
//! Answers the `payload` result ([`crate::protocol::results::PayloadResult`]) once the arm is
//! back; with `apply` the estimate has then become the tool's load.

use super::prelude::*;
use crate::command::IdentifyPayload;

impl Definition for IdentifyPayload {
    const DEF: CommandDef = CommandDef {
        name: "identify_payload",
        kind: Some(CommandKind::IdentifyPayload),
        sends: None,
        success: Success::Payload,
        group: Group::Tool,
        ok_words: "",
        summary: "estimate the load on the flange: move through a few poses and back, measuring",
        args: &[arg(
            "apply",
            "",
            Kind::Bool,
            false,
            "false",
            "make the estimate the tool's mass and centre of mass (its TCP and inertia kept)",
        )],
        modes: "HOLD with the arm at rest, every axis calibrated (the mode stays HOLD while it runs)",
        how: TO_HOLD,
        reply: "the payload result (mass [kg], center_of_mass [m, flange frame], residual [N m]) \
                once the arm is back where it started, in under 30 s",
        examples: &["identify_payload", "identify_payload apply"],
        notes: "The elbow bends 25 degrees either way and the wrist turns up to 90 degrees from \
                where the arm is: leave it room. `hold` aborts it; other commands are refused \
                `busy` meanwhile.",
    };

    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        Ok(IdentifyPayload {
            apply: args.boolean("apply")?.unwrap_or(false),
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("apply".into(), self.apply.into());
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::IdentifyPayload(*self)]
    }
}
