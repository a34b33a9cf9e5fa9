//! `velocity_control`: enter VELOCITY_CONTROL (from HOLD, every axis calibrated), with
//! `timeout` and `dt_status` as `torque_control` has them (the same rows of
//! [`crate::ranges`]). Answers the status after the mode change.

use super::prelude::*;
use super::torque_control::{timing, timing_arguments};
use crate::command;
use crate::protocol::spec::DT_STATUS;

/// `velocity_control`: the request to the core, and what the gateway does itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityControl {
    pub request: command::VelocityControl,
    /// Interval of spontaneous status results [s]; 0: none. The gateway sends them.
    pub dt_status: f64,
}

impl Definition for VelocityControl {
    const DEF: CommandDef = CommandDef {
        name: "velocity_control",
        kind: Some(CommandKind::VelocityControl),
        sends: None,
        success: Success::Status,
        group: Group::ModeChange,
        ok_words: "",
        summary: "enter VELOCITY_CONTROL: joint velocities come from `set_velocities`",
        args: &[
            arg(
                "timeout",
                "",
                Kind::Number,
                true,
                "1",
                "longest time between two `set_velocities` [s]; negative: no timeout; not 0. \
                 When it passes, the axes stop (controlled) and the mode falls back to HOLD",
            ),
            DT_STATUS,
        ],
        modes: IN_HOLD,
        how: TO_HOLD,
        reply: "the status table after the mode change",
        examples: &["velocity_control", "velocity_control timeout=-1"],
        notes: "Velocities are ramped within each axis's acceleration and jerk limits, and a \
                joint driven towards its limit brakes and stops before it. `jog AXIS` drives one \
                axis from the keyboard. `hold` stops and leaves the mode.",
    };

    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        let (timeout_s, dt_status) = timing(args)?;
        Ok(VelocityControl {
            request: command::VelocityControl { timeout_s },
            dt_status,
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        timing_arguments(self.request.timeout_s, self.dt_status)
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::VelocityControl(self.request)]
    }
}
