//! `move_all`: move all axes to target positions, time-synchronised (from rest they start and
//! arrive together), each target within its axis's reachable range. Answers the `move_all`
//! result ([`crate::protocol::results::MoveAllResult`]).

use super::move_axis::velocity_factor;
use super::prelude::*;
use crate::command::MoveAll;
use crate::protocol::spec::VELOCITY_FACTOR;

impl Definition for MoveAll {
    const DEF: CommandDef = CommandDef {
        name: "move_all",
        kind: Some(CommandKind::MoveAll),
        sends: None,
        success: Success::MoveAll,
        group: Group::Pvt,
        ok_words: "",
        summary: "move all axes to target positions; from rest they start and arrive together",
        args: &[
            arg(
                "target_positions",
                "targets",
                Kind::Six,
                true,
                "",
                "six target angles [deg], one per axis, each within its reachable range: its limits \
                 less the safety margin (see below)",
            ),
            VELOCITY_FACTOR,
        ],
        modes: "PVT",
        how: TO_PVT,
        reply: "the velocity of every axis [deg/s], the axis that takes longest and the time to target [s]",
        examples: &[
            "move_all 0 10 20 0 0 0",
            "move_all 0 10 20 0 0 0 vf=0.5",
            "move_all targets=0,10,20,0,0,0",
        ],
        notes: "",
    };

    fn parse(args: &Args<'_>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        Ok(MoveAll {
            targets_deg: args.required_ranged_array(Arg::TargetPositions, cfg)?,
            velocity_factor: velocity_factor(args)?,
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("target_positions".into(), self.targets_deg.to_vec().into());
        m.insert("velocity_factor".into(), self.velocity_factor.into());
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::MoveAll(*self)]
    }
}
