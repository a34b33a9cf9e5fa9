//! `torque_control`: enter TORQUE_CONTROL (from HOLD, every axis calibrated), with `timeout`,
//! `dt_status` and `gravity_compensation`. Answers the status after the mode change; the
//! gateway then sends a status every `dt_status`.

use super::prelude::*;
use crate::command;
use crate::protocol::spec::DT_STATUS;

/// Default `timeout` of `torque_control` and `velocity_control` [s] when none is given.
pub const DEFAULT_MODE_TIMEOUT: f64 = 1.0;

/// `torque_control`: the request to the core, and what the gateway does itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorqueControl {
    pub request: command::TorqueControl,
    /// Interval of spontaneous status results [s]; 0: none. The gateway sends them.
    pub dt_status: f64,
}

/// `timeout` and `dt_status` of `torque_control` and `velocity_control` (the same rows of the
/// table): the core's timeout (`None`: none, a negative `timeout`) and the status interval.
pub(super) fn timing(args: &Args<'_>) -> Result<(Option<f64>, f64), CommandError> {
    let timeout = args
        .ranged(Arg::Timeout, Arg::Timeout.fixed_bounds())?
        .unwrap_or(DEFAULT_MODE_TIMEOUT);
    let dt_status = args
        .ranged(Arg::DtStatus, Arg::DtStatus.fixed_bounds())?
        .unwrap_or(0.0);
    Ok(((timeout > 0.0).then_some(timeout), dt_status))
}

/// The `timeout` and `dt_status` arguments that [`timing`] reads back.
pub(super) fn timing_arguments(timeout_s: Option<f64>, dt_status: f64) -> Map<String, Value> {
    let mut m = Map::new();
    m.insert("timeout".into(), timeout_s.unwrap_or(-1.0).into());
    m.insert("dt_status".into(), dt_status.into());
    m
}

impl Definition for TorqueControl {
    const DEF: CommandDef = CommandDef {
        name: "torque_control",
        kind: Some(CommandKind::TorqueControl),
        sends: None,
        success: Success::Status,
        group: Group::ModeChange,
        ok_words: "",
        summary: "enter TORQUE_CONTROL: joint torques come from `set_torques`",
        args: &[
            arg(
                "timeout",
                "",
                Kind::Number,
                true,
                "1",
                "longest time between two `set_torques` [s]; negative: no timeout; not 0. \
                 When it passes, the mode falls back to HOLD",
            ),
            DT_STATUS,
            arg(
                "gravity_compensation",
                "gravity",
                Kind::Bool,
                false,
                "true",
                "add the model's gravity and friction torques to the given torques",
            ),
        ],
        modes: IN_HOLD,
        how: TO_HOLD,
        reply: "the status table after the mode change",
        examples: &[
            "torque_control -1",
            "torque_control timeout=0.5 gravity=false",
        ],
        notes: "The HMI does not print spontaneous status results; use `watch`.",
    };

    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        let (timeout_s, dt_status) = timing(args)?;
        Ok(TorqueControl {
            request: command::TorqueControl {
                timeout_s,
                gravity_compensation: args.boolean("gravity_compensation")?.unwrap_or(true),
            },
            dt_status,
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = timing_arguments(self.request.timeout_s, self.dt_status);
        m.insert(
            "gravity_compensation".into(),
            self.request.gravity_compensation.into(),
        );
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::TorqueControl(self.request)]
    }
}
