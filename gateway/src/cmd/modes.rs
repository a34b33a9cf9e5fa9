//! The mode-change commands with arguments: `pvt` (with `dt`) and `torque_control`
//! (with `timeout`, `dt_status`, `gravity_compensation`). `hold` and `release` take none.

use super::sample;
use crate::args::{Args, CommandError};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::CommandKind;
use mcm_shared::sample::{CommandSample, TORQUE_FLAG_NO_GRAVITY};
use serde_json::Value;

/// Default spacing of PVT points [s].
pub const DEFAULT_PVT_DT: f64 = 0.01;
/// Default `torque_control` timeout [s] when none is given.
pub const DEFAULT_TORQUE_TIMEOUT: f64 = 1.0;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pvt {
    pub dt: f64,
}

impl Pvt {
    pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        let args = Args::new("pvt", arguments, &["dt"])?;
        let min = cfg.cycle_period_s();
        Ok(Self {
            dt: args
                .number("dt", min, 1.0, " s (at least one cycle)")?
                .unwrap_or(DEFAULT_PVT_DT),
        })
    }

    pub fn sample(&self) -> CommandSample {
        let mut s = sample(CommandKind::Pvt);
        s.args[0] = self.dt;
        s
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorqueControl {
    /// Seconds allowed between `set_torques`; negative: no timeout.
    pub timeout: f64,
    /// Interval of spontaneous status results [s]; 0: none.
    pub dt_status: f64,
    pub gravity_compensation: bool,
}

impl TorqueControl {
    pub fn parse(arguments: Option<&Value>) -> Result<Self, CommandError> {
        let args = Args::new(
            "torque_control",
            arguments,
            &["timeout", "dt_status", "gravity_compensation"],
        )?;
        let timeout = args.number("timeout", f64::MIN, 3600.0, " s (negative: no timeout)")?;
        if timeout == Some(0.0) {
            return Err(args.invalid_value(
                "timeout",
                0,
                "a positive number of seconds, or a negative one for no timeout",
            ));
        }
        Ok(Self {
            timeout: timeout.unwrap_or(DEFAULT_TORQUE_TIMEOUT),
            dt_status: args
                .number("dt_status", 0.0, 60.0, " s (0: no status results)")?
                .unwrap_or(0.0),
            gravity_compensation: args.boolean("gravity_compensation")?.unwrap_or(true),
        })
    }

    pub fn sample(&self) -> CommandSample {
        let mut s = sample(CommandKind::TorqueControl);
        s.args[0] = self.timeout;
        if !self.gravity_compensation {
            s.flags |= TORQUE_FLAG_NO_GRAVITY;
        }
        s
    }
}
