//! The mode-change commands with arguments: `pvt` (with `dt`) and `torque_control`
//! (with `timeout`, `dt_status`, `gravity_compensation`). `hold` and `release` take none.

use crate::args::{Args, CommandError};
use mcm_shared::command::{self, Pvt};
use mcm_shared::config::RobotConfig;
use mcm_shared::ranges::Arg;
use serde_json::Value;

/// Default spacing of PVT points [s].
pub const DEFAULT_PVT_DT: f64 = 0.01;
/// Default `timeout` of `torque_control` and `velocity_control` [s] when none is given.
pub const DEFAULT_MODE_TIMEOUT: f64 = 1.0;

/// Parse the arguments of `pvt`: `dt` from one cycle to [`Pvt::MAX_DT_S`] ([`Arg::Dt`]).
pub fn parse_pvt(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<Pvt, CommandError> {
    let args = Args::new("pvt", arguments, &["dt"])?;
    Ok(Pvt {
        dt_s: args
            .ranged(Arg::Dt, Arg::Dt.bounds(cfg, None))?
            .unwrap_or(DEFAULT_PVT_DT),
    })
}

/// `torque_control`: the request to the core, and what the gateway does itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorqueControl {
    pub request: command::TorqueControl,
    /// Interval of spontaneous status results [s]; 0: none. The gateway sends them.
    pub dt_status: f64,
}

impl TorqueControl {
    pub fn parse(arguments: Option<&Value>) -> Result<Self, CommandError> {
        let args = Args::new(
            "torque_control",
            arguments,
            &["timeout", "dt_status", "gravity_compensation"],
        )?;
        let (timeout_s, dt_status) = timing(&args)?;
        Ok(Self {
            request: command::TorqueControl {
                timeout_s,
                gravity_compensation: args.boolean("gravity_compensation")?.unwrap_or(true),
            },
            dt_status,
        })
    }
}

/// `timeout` and `dt_status` of `torque_control` and `velocity_control` (the same rows of the
/// table): the core's timeout (`None`: none, a negative `timeout`) and the status interval.
pub(super) fn timing(args: &Args) -> Result<(Option<f64>, f64), CommandError> {
    let timeout = args
        .ranged(Arg::Timeout, Arg::Timeout.fixed_bounds())?
        .unwrap_or(DEFAULT_MODE_TIMEOUT);
    let dt_status = args
        .ranged(Arg::DtStatus, Arg::DtStatus.fixed_bounds())?
        .unwrap_or(0.0);
    Ok(((timeout > 0.0).then_some(timeout), dt_status))
}
