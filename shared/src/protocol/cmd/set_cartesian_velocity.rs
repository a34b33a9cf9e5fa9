//! `set_cartesian_velocity`: the TCP's velocity in VELOCITY_CONTROL, linear [m/s] and angular
//! [deg/s], in the base frame or the TCP's own (`frame`). Each component within its fixed
//! range ([`Arg::Linear`], [`Arg::Angular`]: the rows the real-time core's decoding checks
//! too). Answers nothing on success, as `set_velocities`; a refusal comes as an ERROR.

use super::prelude::*;
use crate::command::{CartesianFrame, SetCartesianVelocity};

/// What `frame` takes, for its refusal.
const FRAME_EXPECTED: &str = "\"base\" or \"tool\"";

impl Definition for SetCartesianVelocity {
    const DEF: CommandDef = CommandDef {
        name: "set_cartesian_velocity",
        kind: Some(CommandKind::SetCartesianVelocity),
        sends: None,
        success: Success::Nothing,
        group: Group::VelocityControl,
        ok_words: " - TCP velocity set",
        summary: "the TCP's velocity (linear and angular) in VELOCITY_CONTROL",
        args: &[
            arg(
                "linear",
                "",
                Kind::Vector,
                true,
                "",
                "[3 m/s]: the TCP's linear velocity, each component from -1 to 1 m/s",
            ),
            arg(
                "angular",
                "",
                Kind::Vector,
                true,
                "",
                "[3 deg/s]: the TCP's angular velocity, each component from -180 to 180 deg/s",
            ),
            arg(
                "frame",
                "",
                Kind::Text,
                true,
                "base",
                "the frame whose axes the velocities are in: base, or tool (the TCP's frame \
                 as it turns)",
            ),
        ],
        modes: "VELOCITY_CONTROL",
        how: "enter VELOCITY_CONTROL first: `hold`, then `velocity_control`",
        reply: "OK (the JSON channel answers nothing on success)",
        examples: &[
            "set_cartesian_velocity 0.05 0 0 0 0 0",
            "set_cartesian_velocity 0,0,0.02 0,0,0 tool",
        ],
        notes: "Send it again before the timeout passes, or the arm stops. The axes follow \
                within their velocity, acceleration and jerk limits; where an axis would \
                exceed its velocity or come too near its limit the whole motion slows along \
                the same direction, and near a singularity the motion towards it slows.",
    };

    fn parse(args: &Args<'_>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        let frame = match args.raw("frame") {
            None => CartesianFrame::default(),
            Some(v) => v
                .as_str()
                .and_then(CartesianFrame::from_name)
                .ok_or_else(|| args.invalid("frame", v, FRAME_EXPECTED))?,
        };
        Ok(SetCartesianVelocity {
            linear_m_s: args.required_ranged_array(Arg::Linear, cfg)?,
            angular_deg_s: args.required_ranged_array(Arg::Angular, cfg)?,
            frame,
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("linear".into(), self.linear_m_s.to_vec().into());
        m.insert("angular".into(), self.angular_deg_s.to_vec().into());
        m.insert("frame".into(), self.frame.as_str().into());
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::SetCartesianVelocity(*self)]
    }
}
