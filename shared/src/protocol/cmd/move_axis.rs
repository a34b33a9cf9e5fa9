//! `move_axis`: move one axis to a target position (PVT mode), the target within the axis's
//! reachable range. Answers OK as the motion starts.

use super::prelude::*;
use crate::command::MoveAxis;
use crate::protocol::spec::VELOCITY_FACTOR;

/// The default `velocity_factor` of the manual.
pub const DEFAULT_VELOCITY_FACTOR: f64 = 0.33333;

/// The optional `velocity_factor` ([`Arg::VelocityFactor`]), default
/// [`DEFAULT_VELOCITY_FACTOR`].
pub(super) fn velocity_factor(args: &Args<'_>) -> Result<f64, CommandError> {
    let vf = Arg::VelocityFactor;
    Ok(args
        .ranged(vf, vf.fixed_bounds())?
        .unwrap_or(DEFAULT_VELOCITY_FACTOR))
}

impl Definition for MoveAxis {
    const DEF: CommandDef = CommandDef {
        name: "move_axis",
        kind: Some(CommandKind::MoveAxis),
        sends: None,
        success: Success::Ok,
        group: Group::Pvt,
        ok_words: " - the axis is moving (`watch` follows it)",
        summary: "move one axis to a target position",
        args: &[
            arg("axis_index", "axis", Kind::Axis, true, "", "the axis, 1..6"),
            arg(
                "target_position",
                "target",
                Kind::Number,
                true,
                "",
                "target angle [deg], within the axis's reachable range: its limits less the safety \
                 margin (see below)",
            ),
            VELOCITY_FACTOR,
        ],
        modes: "PVT",
        how: TO_PVT,
        reply: "OK as soon as the motion starts (`watch` follows it)",
        examples: &[
            "move_axis 1 30",
            "move_axis 1 30 0.5",
            "move_axis axis=2 target=-45 vf=0.2",
        ],
        notes: "",
    };

    fn parse(args: &Args<'_>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        let axis = args.required_axis(Arg::AxisIndex)?;
        let target_deg = args.required_ranged(
            Arg::TargetPosition,
            Arg::TargetPosition.bounds(cfg, Some(axis.index())),
        )?;
        Ok(MoveAxis {
            axis,
            target_deg,
            velocity_factor: velocity_factor(args)?,
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("axis_index".into(), self.axis.number().into());
        m.insert("target_position".into(), self.target_deg.into());
        m.insert("velocity_factor".into(), self.velocity_factor.into());
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::MoveAxis(*self)]
    }
}
