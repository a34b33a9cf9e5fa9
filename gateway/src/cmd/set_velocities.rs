//! `set_velocities`: the joint velocities of all axes in VELOCITY_CONTROL mode [deg/s].

use crate::args::{Args, CommandError};
use mcm_shared::command::SetVelocities;
use mcm_shared::config::RobotConfig;
use serde_json::Value;

/// Parse the arguments of `set_velocities`, each velocity within its axis's maximum velocity.
pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<SetVelocities, CommandError> {
    let args = Args::new("set_velocities", arguments, &["velocities"])?;
    let velocities_deg_s = args.required_six("velocities", "velocities [deg/s]", |i, v| {
        let max = cfg.axes[i].max_velocity_deg_s;
        if v.abs() > max {
            Err(format!(
                "a velocity of axis {} from {} to {max} deg/s (its maximum velocity)",
                i + 1,
                -max
            ))
        } else {
            Ok(())
        }
    })?;
    Ok(SetVelocities { velocities_deg_s })
}
