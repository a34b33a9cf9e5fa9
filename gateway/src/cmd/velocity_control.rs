//! `velocity_control`: enter VELOCITY_CONTROL (from HOLD), with `timeout` and `dt_status` as
//! `torque_control` has them (the same rows of [`mcm_shared::ranges`]).

use super::modes::DEFAULT_TORQUE_TIMEOUT;
use crate::args::{Args, CommandError};
use mcm_shared::command;
use mcm_shared::ranges::Arg;
use serde_json::Value;

/// Default `velocity_control` timeout [s] when none is given (the same as `torque_control`'s).
pub const DEFAULT_VELOCITY_TIMEOUT: f64 = DEFAULT_TORQUE_TIMEOUT;

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
        // The same `timeout` and `dt_status` as `torque_control`'s (one row each).
        let timeout = args.ranged(Arg::Timeout, Arg::Timeout.fixed_bounds())?;
        let timeout = timeout.unwrap_or(DEFAULT_VELOCITY_TIMEOUT);
        Ok(Self {
            request: command::VelocityControl {
                timeout_s: (timeout > 0.0).then_some(timeout),
            },
            dt_status: args
                .ranged(Arg::DtStatus, Arg::DtStatus.fixed_bounds())?
                .unwrap_or(0.0),
        })
    }
}
