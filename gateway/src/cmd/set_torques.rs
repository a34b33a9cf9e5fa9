//! `set_torques`: the torques of all axes in TORQUE_CONTROL mode [Nm].

use crate::args::{Args, CommandError};
use mcm_shared::command::SetTorques;
use mcm_shared::config::RobotConfig;
use serde_json::Value;

/// Parse the arguments of `set_torques`, each torque within its axis's peak joint torque.
pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<SetTorques, CommandError> {
    let args = Args::new("set_torques", arguments, &["torques"])?;
    let torques_nm = args.required_six("torques", "torques [Nm]", |i, t| {
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
    Ok(SetTorques { torques_nm })
}
