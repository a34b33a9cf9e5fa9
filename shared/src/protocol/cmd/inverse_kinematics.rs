//! `inverse_kinematics`: every joint configuration that puts the TCP at a pose, each within
//! the axes' reachable ranges, the nearest to a seed (by default the present position) first.
//! A computation, not a motion: executed by the gateway, in every mode, for every client;
//! answers the `inverse_kinematics` result
//! ([`crate::protocol::results::InverseKinematicsResult`]).

use super::prelude::*;
use crate::protocol::args::six_numbers;
use crate::protocol::pose::{ORIENTATION, POSITION, Pose};

/// `inverse_kinematics`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InverseKinematics {
    /// Where the TCP is to be.
    pub pose: Pose,
    /// The configuration the solutions are sorted by nearness to [deg]; `None`: the present
    /// position.
    pub seed_deg: Option<[f64; 6]>,
}

impl Definition for InverseKinematics {
    const DEF: CommandDef = CommandDef {
        name: "inverse_kinematics",
        kind: None,
        sends: None,
        success: Success::InverseKinematics,
        group: Group::EveryMode,
        ok_words: "",
        summary: "the joint positions that put the TCP at a pose, nearest the seed first",
        args: &[
            POSITION,
            ORIENTATION,
            arg(
                "seed",
                "",
                Kind::Six,
                false,
                "",
                "six joint angles [deg] the solutions are sorted by nearness to; default: the \
                 present position (which needs every axis calibrated)",
            ),
        ],
        modes: "every mode",
        how: "",
        reply: "every solution within the axis limits [deg], the nearest to the seed first; \
                ERROR `unreachable` when there is none",
        examples: &[
            "inverse_kinematics 0.4 0 0.5 0 1 0 0",
            "inverse_kinematics pos=0.4,0,0.5 orient=0,1,0,0 seed=0,10,20,0,0,0",
        ],
        notes: "Nothing moves. The TCP is the active tool's; nearness is the time the slowest \
                axis needs at its maximum velocity (`docs/cartesian.md`).",
    };

    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        let pose = Pose::parse(args)?;
        let seed_deg = match args.raw("seed") {
            None => None,
            Some(v) => Some(six_numbers(args, "seed", v, "joint angles [deg]")?),
        };
        Ok(InverseKinematics { pose, seed_deg })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        self.pose.insert_into(&mut m);
        if let Some(seed) = self.seed_deg {
            m.insert("seed".into(), seed.to_vec().into());
        }
        m
    }

    fn requests(&self) -> Vec<Request> {
        Vec::new()
    }
}
