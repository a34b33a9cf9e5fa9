//! `set_torques`: the torques of all axes in TORQUE_CONTROL mode [Nm].

use super::sample;
use crate::args::{Args, CommandError};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::CommandKind;
use mcm_shared::sample::CommandSample;
use serde_json::Value;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetTorques {
    pub torques: [f64; 6],
}

impl SetTorques {
    pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        let args = Args::new("set_torques", arguments, &["torques"])?;
        let torques = args.required_six("torques", "torques [Nm]", |i, t| {
            let a = &cfg.axes[i];
            let peak = a.max_current_a * a.torque_per_amp();
            if t.abs() > peak {
                Err(format!(
                    "a torque of axis {} within +-{peak:.1} Nm (its peak joint torque)",
                    i + 1
                ))
            } else {
                Ok(())
            }
        })?;
        Ok(Self { torques })
    }

    pub fn sample(&self) -> CommandSample {
        let mut s = sample(CommandKind::SetTorques);
        s.args[..6].copy_from_slice(&self.torques);
        s
    }
}
