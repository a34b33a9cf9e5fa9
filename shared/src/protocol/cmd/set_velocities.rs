//! `set_velocities`: the joint velocities of all axes in VELOCITY_CONTROL [deg/s], each within
//! its axis's maximum velocity ([`Arg::Velocities`]: the range the real-time core checks too).
//! Answers nothing on success; a refusal comes as an ERROR.

use super::prelude::*;
use crate::command::SetVelocities;

impl Definition for SetVelocities {
    const DEF: CommandDef = CommandDef {
        name: "set_velocities",
        kind: Some(CommandKind::SetVelocities),
        sends: None,
        success: Success::Nothing,
        group: Group::VelocityControl,
        ok_words: " - velocities set",
        summary: "the joint velocities of all six axes in VELOCITY_CONTROL",
        args: &[arg(
            "velocities",
            "",
            Kind::Six,
            true,
            "",
            "six velocities [deg/s], one per axis, each within the axis's maximum velocity \
             (see below)",
        )],
        modes: "VELOCITY_CONTROL",
        how: "enter VELOCITY_CONTROL first: `hold`, then `velocity_control`",
        reply: "OK (the JSON channel answers nothing on success)",
        examples: &["set_velocities 0 10 0 0 0 0", "set_velocities 0,0,-5,0,0,0"],
        notes: "Send them again before the timeout passes, or the axes stop.",
    };

    fn parse(args: &Args<'_>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        Ok(SetVelocities {
            velocities_deg_s: args.required_ranged_array(Arg::Velocities, cfg)?,
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("velocities".into(), self.velocities_deg_s.to_vec().into());
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::SetVelocities(*self)]
    }
}
