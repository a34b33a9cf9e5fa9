//! `set_torques`: the torques of all axes in TORQUE_CONTROL mode [Nm].

use crate::args::{Args, CommandError};
use mcm_shared::command::SetTorques;
use mcm_shared::config::RobotConfig;
use mcm_shared::ranges::Arg;
use serde_json::Value;

/// Parse the arguments of `set_torques`, each torque within its axis's peak joint torque.
pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<SetTorques, CommandError> {
    let args = Args::new("set_torques", arguments, &["torques"])?;
    let torques_nm = args.required_ranged_six(Arg::Torques, cfg)?;
    Ok(SetTorques { torques_nm })
}
