//! `velocity_control`: enter VELOCITY_CONTROL (from HOLD), with `timeout` and `dt_status` as
//! `torque_control` has them (the same rows of [`mcm_shared::ranges`]).

use super::modes::timing;
use crate::args::{Args, CommandError};
use mcm_shared::command;
use serde_json::Value;

/// `velocity_control`: the request to the core, and what the gateway does itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityControl {
    pub request: command::VelocityControl,
    /// Interval of spontaneous status results [s]; 0: none. The gateway sends them.
    pub dt_status: f64,
}

impl VelocityControl {
    pub fn parse(arguments: Option<&Value>) -> Result<Self, CommandError> {
        let args = Args::new("velocity_control", arguments, &["timeout", "dt_status"])?;
        let (timeout_s, dt_status) = timing(&args)?;
        Ok(Self {
            request: command::VelocityControl { timeout_s },
            dt_status,
        })
    }
}
