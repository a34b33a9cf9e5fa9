//! `move_to_pose`: a joint move of all axes (as `move_all`) to the inverse kinematics'
//! solution nearest the present position. Executed by the gateway, which solves the pose and
//! sends the core the `move_all` request ([`CommandDef::sends`]): the core's rules on mode,
//! control, range and re-planning apply as to `move_all`, and the answer is the `move_all`
//! result. A pose no solution reaches is refused before anything is sent.

use super::move_axis::velocity_factor;
use super::prelude::*;
use crate::protocol::pose::{ORIENTATION, POSITION, Pose};
use crate::protocol::spec::VELOCITY_FACTOR;

/// `move_to_pose`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveToPose {
    /// Where the TCP is to go.
    pub pose: Pose,
    /// As `move_all`'s.
    pub velocity_factor: f64,
}

impl Definition for MoveToPose {
    const DEF: CommandDef = CommandDef {
        name: "move_to_pose",
        kind: None,
        sends: Some(CommandKind::MoveAll),
        success: Success::MoveAll,
        group: Group::Pvt,
        ok_words: "",
        summary: "move the TCP to a pose: a joint move to the solution nearest the present position",
        args: &[POSITION, ORIENTATION, VELOCITY_FACTOR],
        modes: "PVT",
        how: TO_PVT,
        reply: "as `move_all`: the velocity of every axis [deg/s], the axis that takes longest \
                and the time to target [s]; ERROR `unreachable` when no solution reaches the pose",
        examples: &[
            "move_to_pose 0.4 0 0.5 0 1 0 0",
            "move_to_pose pos=0.4,0,0.5 orient=0,1,0,0 vf=0.5",
        ],
        notes: "The TCP moves on the joint move's path, not on a straight line. The TCP is the \
                active tool's (`docs/cartesian.md`).",
    };

    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        Ok(MoveToPose {
            pose: Pose::parse(args)?,
            velocity_factor: velocity_factor(args)?,
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        self.pose.insert_into(&mut m);
        m.insert("velocity_factor".into(), self.velocity_factor.into());
        m
    }

    /// None of its own: the gateway sends the `move_all` of the solution it chose.
    fn requests(&self) -> Vec<Request> {
        Vec::new()
    }
}
