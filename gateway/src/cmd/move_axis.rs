//! `move_axis`: move one axis to a target position (PVT mode).

use super::{DEFAULT_VELOCITY_FACTOR, check_position};
use crate::args::{Args, CommandError};
use mcm_shared::command::MoveAxis;
use mcm_shared::config::RobotConfig;
use serde_json::Value;

/// Parse the arguments of `move_axis`, the target within the axis's limits.
pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<MoveAxis, CommandError> {
    let args = Args::new(
        "move_axis",
        arguments,
        &["axis_index", "target_position", "velocity_factor"],
    )?;
    let axis = args.required_axis("axis_index")?;
    let a = &cfg.axes[axis.index()];
    let target_deg = args.required_number("target_position", a.min_deg, a.max_deg, " deg")?;
    let velocity_factor = velocity_factor(&args)?;
    check_position(cfg, axis.index(), target_deg)
        .map_err(|e| args.invalid_value("target_position", target_deg, e))?;
    Ok(MoveAxis {
        axis,
        target_deg,
        velocity_factor,
    })
}

/// The optional `velocity_factor`: (0, 1], default 0.33333.
pub fn velocity_factor(args: &Args<'_>) -> Result<f64, CommandError> {
    let f = args
        .number(
            "velocity_factor",
            0.0,
            1.0,
            " (a fraction of the maximum velocity)",
        )?
        .unwrap_or(DEFAULT_VELOCITY_FACTOR);
    if f <= 0.0 {
        return Err(args.invalid_value("velocity_factor", f, "a number above 0 and at most 1"));
    }
    Ok(f)
}
