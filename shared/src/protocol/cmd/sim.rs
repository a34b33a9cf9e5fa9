//! `sim`: fault injection into the simulated robot (refused on real hardware by the real-time
//! core). Any combination of arguments; the reply is the `sim` result with the ground truth
//! ([`crate::protocol::results::SimResult`]).

use super::prelude::*;
use crate::command::SimCommand;

impl Definition for SimCommand {
    const DEF: CommandDef = CommandDef {
        name: "sim",
        kind: Some(CommandKind::Sim),
        sends: None,
        success: Success::Sim,
        group: Group::EveryMode,
        ok_words: "",
        summary: "fault injection into the simulated robot",
        args: &[
            arg(
                "emergency_stop",
                "estop",
                Kind::Bool,
                false,
                "",
                "press (true) or release (false) the emergency switch",
            ),
            arg(
                "disconnect_axis",
                "",
                Kind::Axis,
                false,
                "",
                "drive 1..6 goes silent on the bus",
            ),
            arg(
                "reconnect_axis",
                "",
                Kind::Axis,
                false,
                "",
                "drive 1..6 comes back",
            ),
            arg(
                "block_axis",
                "",
                Kind::Axis,
                false,
                "",
                "a rigid obstacle holds axis 1..6 where it is",
            ),
            arg(
                "unblock_axis",
                "",
                Kind::Axis,
                false,
                "",
                "remove the obstacle of axis 1..6",
            ),
            arg(
                "external_torques",
                "torques",
                Kind::Six,
                false,
                "",
                "six torques [Nm] of a hand pushing on the joints, until set back to zeros",
            ),
            arg(
                "true_tool",
                "",
                Kind::Json,
                false,
                "",
                "{\"mass\": kg, \"center_of_mass\": [3 m]}: the load the arm really carries \
                 (flange frame), whatever set_tool says",
            ),
            arg(
                "power_cycle",
                "",
                Kind::Bool,
                false,
                "false",
                "the drives lose power and reboot: calibration is lost",
            ),
        ],
        modes: "every mode; simulated robot only",
        how: "",
        reply: "the simulation's ground truth: true positions and velocities, emergency switch",
        examples: &[
            "sim estop=true",
            "sim block_axis=2",
            "sim external_torques=0,5,0,0,0,0",
            "sim power_cycle",
        ],
        notes: "Any combination of arguments in one command. Refused on real hardware.",
    };

    /// The arguments not given change nothing.
    fn parse(args: &Args<'_>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        Ok(SimCommand {
            emergency_stop: args.boolean("emergency_stop")?,
            disconnect_axis: args.axis(Arg::DisconnectAxis)?,
            reconnect_axis: args.axis(Arg::ReconnectAxis)?,
            block_axis: args.axis(Arg::BlockAxis)?,
            unblock_axis: args.axis(Arg::UnblockAxis)?,
            external_torques_nm: args.ranged_array(Arg::ExternalTorques, cfg)?,
            power_cycle: args.boolean("power_cycle")?.unwrap_or(false),
            true_tool: true_tool(args)?,
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        if let Some(e) = self.emergency_stop {
            m.insert("emergency_stop".into(), e.into());
        }
        for (key, axis) in [
            ("disconnect_axis", self.disconnect_axis),
            ("reconnect_axis", self.reconnect_axis),
            ("block_axis", self.block_axis),
            ("unblock_axis", self.unblock_axis),
        ] {
            if let Some(a) = axis {
                m.insert(key.into(), a.number().into());
            }
        }
        if let Some(t) = self.external_torques_nm {
            m.insert("external_torques".into(), t.to_vec().into());
        }
        if self.power_cycle {
            m.insert("power_cycle".into(), true.into());
        }
        if let Some(t) = self.true_tool {
            let mut load = Map::new();
            load.insert("mass".into(), t.mass.into());
            load.insert("center_of_mass".into(), t.center_of_mass.to_vec().into());
            m.insert("true_tool".into(), load.into());
        }
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::Sim(*self)]
    }
}

/// `true_tool` `{"mass","center_of_mass"}`, checked as a tool's load is.
fn true_tool(args: &Args<'_>) -> Result<Option<crate::tool::Tool>, CommandError> {
    const EXPECTED: &str = "an object {\"mass\": kg, \"center_of_mass\": [3 m]}";
    let Some(v) = args.raw("true_tool") else {
        return Ok(None);
    };
    let o = v
        .as_object()
        .filter(|o| o.len() == 2 && o.contains_key("mass") && o.contains_key("center_of_mass"))
        .ok_or_else(|| args.invalid("true_tool", v, EXPECTED))?;
    let mass = o["mass"]
        .as_f64()
        .ok_or_else(|| args.invalid("true_tool.mass", &o["mass"], "a number [kg]"))?;
    let com = crate::protocol::args::numbers(
        args,
        "true_tool.center_of_mass",
        &o["center_of_mass"],
        "numbers [m]",
    )?;
    SimCommand::true_tool(mass, com)
        .map(Some)
        .map_err(|error| CommandError::Tool {
            command: SimCommand::DEF.name,
            error,
        })
}
