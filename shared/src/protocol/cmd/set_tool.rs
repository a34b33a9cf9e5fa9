//! `set_tool`: the tool the arm carries (its TCP and its load), from the next cycle, for every
//! use of the arm's model in the real-time core. Checked by [`Tool::new`], the check the core
//! and the configuration's `[arm.tool]` use; a refusal is `out_of_range` naming the value.
//! [`tool_json`] writes a tool as `set_tool` takes it, as `status` `detail.tool` shows it.

use super::prelude::*;
use crate::command::SetTool;
use crate::protocol::args::numbers;
use crate::tool::{Tcp, Tool};

/// The `tcp` argument, as the refusals of its shape say it.
const TCP_EXPECTED: &str =
    "an object {\"position\":[3 m],\"orientation\":[x, y, z, w]} (the TCP in the flange frame)";

impl Definition for SetTool {
    const DEF: CommandDef = CommandDef {
        name: "set_tool",
        kind: Some(CommandKind::SetTool),
        sends: None,
        success: Success::Ok,
        group: Group::Tool,
        ok_words: " - tool set",
        summary: "the tool the arm carries: its TCP and its load, from the next cycle",
        args: &[
            arg(
                "tcp",
                "",
                Kind::Json,
                false,
                "",
                "{\"position\":[3 m],\"orientation\":[x,y,z,w]}: the TCP in the flange frame, \
                 within 0.5 m of it; the orientation a unit quaternion (norm 1 within 0.001)",
            ),
            arg(
                "mass",
                "",
                Kind::Number,
                false,
                "",
                "the tool's mass with its payload [kg], from 0 to 5",
            ),
            arg(
                "center_of_mass",
                "com",
                Kind::Json,
                false,
                "",
                "[3 m]: its centre of mass in the flange frame, within 0.5 m of the flange",
            ),
            arg(
                "inertia",
                "",
                Kind::Json,
                false,
                "[0,0,0,0,0,0]",
                "[ixx,iyy,izz,ixy,ixz,iyz] [kg m^2] about the centre of mass, flange axes: \
                 a body's inertia (the default: a point mass)",
            ),
        ],
        modes: "HOLD, or PVT with the arm at standstill",
        how: "`hold` first, or wait until the PVT motion has ended",
        reply: "OK; gravity and friction compensation, torque control and the safety model use \
                the new tool from the next cycle",
        examples: &[
            "set_tool tcp={\"position\":[0,0,0.15],\"orientation\":[0,0,0,1]} mass=2 com=[0,0,0.06]",
        ],
        notes: "The configuration's [arm.tool] is the tool at start. `status` shows the active \
                tool in `detail.tool`.",
    };

    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        let tcp = args
            .raw("tcp")
            .ok_or_else(|| args.missing("tcp", TCP_EXPECTED))?;
        let tcp = tcp
            .as_object()
            .filter(|o| o.len() == 2 && o.contains_key("position") && o.contains_key("orientation"))
            .ok_or_else(|| args.invalid("tcp", tcp, TCP_EXPECTED))?;
        let tcp = Tcp {
            position: numbers(args, "tcp.position", &tcp["position"], "numbers [m]")?,
            orientation: numbers(
                args,
                "tcp.orientation",
                &tcp["orientation"],
                "numbers (a unit quaternion x, y, z, w)",
            )?,
        };
        let mass = args
            .raw("mass")
            .ok_or_else(|| args.missing("mass", "a number [kg] from 0 to 5"))?;
        let mass = mass
            .as_f64()
            .ok_or_else(|| args.invalid("mass", mass, "a number [kg] from 0 to 5"))?;
        let com = args
            .raw("center_of_mass")
            .ok_or_else(|| args.missing("center_of_mass", "an array of 3 numbers [m]"))?;
        let center_of_mass = numbers(args, "center_of_mass", com, "numbers [m]")?;
        let inertia = args
            .raw("inertia")
            .map(|v| numbers(args, "inertia", v, "numbers [kg m^2]"))
            .transpose()?;
        let tool =
            Tool::new(tcp, mass, center_of_mass, inertia).map_err(|error| CommandError::Tool {
                command: Self::DEF.name,
                error,
            })?;
        Ok(SetTool { tool })
    }

    fn arguments(&self) -> Map<String, Value> {
        tool_json(&self.tool)
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::SetTool(*self)]
    }
}

/// A tool as `set_tool` takes it: `{"tcp":{"position","orientation"},"mass","center_of_mass",
/// "inertia"}` (the inertia zeros for a point mass); [`Tool`]'s own JSON.
pub fn tool_json(tool: &Tool) -> Map<String, Value> {
    match serde_json::to_value(tool) {
        Ok(Value::Object(m)) => m,
        _ => Map::new(),
    }
}
