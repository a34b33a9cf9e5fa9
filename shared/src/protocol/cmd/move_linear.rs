//! `move_linear`: the TCP on a straight line to a position, the orientation turned on the
//! shortest arc (kept when absent), time-scaled within the TCP's requested speed and
//! acceleration and every axis's limits. Executed by the real-time core, which has the whole
//! path checked (reach, singularities, axis ranges) before anything moves and answers the
//! `move_linear` result ([`crate::protocol::results::MoveLinearResult`]) once the line is
//! planned (`docs/cartesian.md`).

use super::prelude::*;
use crate::command::MoveLinear;
use crate::protocol::pose::{POSITION, Pose};

/// Its `orientation`: as the pose commands', but optional.
const ORIENTATION: crate::protocol::ArgDef = arg(
    "orientation",
    "orient",
    Kind::Orientation,
    false,
    "",
    "the TCP's orientation at the target in the base frame: a unit quaternion x, y, z, w \
     (normalised when its norm is within 0.001 of 1), reached on the shortest arc; absent: \
     the present orientation is kept",
);

impl Definition for MoveLinear {
    const DEF: CommandDef = CommandDef {
        name: "move_linear",
        kind: Some(CommandKind::MoveLinear),
        sends: None,
        success: Success::MoveLinear,
        group: Group::Pvt,
        ok_words: "",
        summary: "move the TCP on a straight line to a position (and orientation)",
        args: &[
            POSITION,
            ORIENTATION,
            arg(
                "velocity",
                "v",
                Kind::Number,
                false,
                "",
                "the TCP's speed [m/s], from 0.001 to 1; absent: 0.25",
            ),
            arg(
                "acceleration",
                "a",
                Kind::Number,
                false,
                "",
                "the TCP's acceleration [m/s^2], from 0.01 to 10; absent: 1.2",
            ),
        ],
        modes: "PVT",
        how: TO_PVT,
        reply: "the time to the target [s] and each axis's position there [deg], once the line \
                is planned; ERROR `unreachable` (beyond the reach, too near a singularity, an \
                axis that cannot follow) or `out_of_range` (an axis beyond its reachable range) \
                naming where on the path, and nothing moves",
        examples: &[
            "move_linear 0.4 0 0.5",
            "move_linear pos=0.4,0,0.5 orient=0,1,0,0 v=0.1",
        ],
        notes: "The whole path is checked before anything moves. During a move the arm first \
                comes to rest, then the line starts from there. The TCP is the active tool's \
                (`docs/cartesian.md`).",
    };

    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        let fixed = |arg: Arg| args.ranged(arg, arg.fixed_bounds());
        Ok(MoveLinear {
            position: Pose::position(args)?,
            orientation: Pose::orientation(args)?,
            velocity: fixed(Arg::LinearVelocity)?,
            acceleration: fixed(Arg::LinearAcceleration)?,
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("position".into(), self.position.to_vec().into());
        if let Some(q) = self.orientation {
            m.insert("orientation".into(), q.to_vec().into());
        }
        if let Some(v) = self.velocity {
            m.insert("velocity".into(), v.into());
        }
        if let Some(a) = self.acceleration {
            m.insert("acceleration".into(), a.into());
        }
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::MoveLinear(*self)]
    }
}
