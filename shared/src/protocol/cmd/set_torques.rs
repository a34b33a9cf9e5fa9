//! `set_torques`: the joint torques of all axes in TORQUE_CONTROL [Nm], each within its axis's
//! peak joint torque. Answers nothing on success; a refusal comes as an ERROR.

use super::prelude::*;
use crate::command::SetTorques;

impl Definition for SetTorques {
    const DEF: CommandDef = CommandDef {
        name: "set_torques",
        kind: Some(CommandKind::SetTorques),
        sends: None,
        success: Success::Nothing,
        group: Group::TorqueControl,
        ok_words: " - torques set",
        summary: "the joint torques of all six axes in TORQUE_CONTROL",
        args: &[arg(
            "torques",
            "",
            Kind::Six,
            true,
            "",
            "six torques [Nm], one per axis, each within the axis's peak torque (see below)",
        )],
        modes: "TORQUE_CONTROL",
        how: "enter TORQUE_CONTROL first: `hold`, then `torque_control`",
        reply: "OK (the JSON channel answers nothing on success)",
        examples: &["set_torques 0 0 0 0 0 0", "set_torques 0,0,1.5,0,0,0"],
        notes: "Zero torques hold the arm still while gravity compensation is on.",
    };

    fn parse(args: &Args<'_>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        Ok(SetTorques {
            torques_nm: args.required_ranged_array(Arg::Torques, cfg)?,
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("torques".into(), self.torques_nm.to_vec().into());
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::SetTorques(*self)]
    }
}
