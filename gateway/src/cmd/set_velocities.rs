//! `set_velocities`: the joint velocities of all axes in VELOCITY_CONTROL mode [deg/s].

use crate::args::{Args, CommandError};
use mcm_shared::command::SetVelocities;
use mcm_shared::config::RobotConfig;
use mcm_shared::ranges::Arg;
use serde_json::Value;

/// Parse the arguments of `set_velocities`, each velocity within its axis's maximum velocity
/// ([`Arg::Velocities`]: the range the real-time core checks too).
pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<SetVelocities, CommandError> {
    let args = Args::new("set_velocities", arguments, &["velocities"])?;
    let velocities_deg_s = args.required_ranged_six(Arg::Velocities, cfg)?;
    Ok(SetVelocities { velocities_deg_s })
}
