//! `move_axis`: move one axis to a target position (PVT mode).

use super::DEFAULT_VELOCITY_FACTOR;
use crate::args::{Args, CommandError};
use mcm_shared::command::MoveAxis;
use mcm_shared::config::RobotConfig;
use mcm_shared::ranges::Arg;
use serde_json::Value;

/// Parse the arguments of `move_axis`, the target within the axis's reachable range.
pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<MoveAxis, CommandError> {
    let args = Args::new(
        "move_axis",
        arguments,
        &["axis_index", "target_position", "velocity_factor"],
    )?;
    let axis = args.required_axis("axis_index")?;
    let target_deg = args.required_ranged(
        Arg::TargetPosition,
        Arg::TargetPosition.bounds(cfg, Some(axis.index())),
    )?;
    Ok(MoveAxis {
        axis,
        target_deg,
        velocity_factor: velocity_factor(&args)?,
    })
}

/// The optional `velocity_factor` ([`Arg::VelocityFactor`]), default 0.33333.
pub fn velocity_factor(args: &Args<'_>) -> Result<f64, CommandError> {
    let vf = Arg::VelocityFactor;
    Ok(args
        .ranged(vf, vf.fixed_bounds())?
        .unwrap_or(DEFAULT_VELOCITY_FACTOR))
}
