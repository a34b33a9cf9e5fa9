//! `move_axis`: move one axis to a target position (PVT mode).

use super::{DEFAULT_VELOCITY_FACTOR, check_position, sample};
use crate::args::{Args, CommandError};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::CommandKind;
use mcm_shared::sample::CommandSample;
use serde_json::Value;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveAxis {
    /// 1..=6.
    pub axis: usize,
    /// [deg]
    pub target: f64,
    pub velocity_factor: f64,
}

impl MoveAxis {
    pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        let args = Args::new(
            "move_axis",
            arguments,
            &["axis_index", "target_position", "velocity_factor"],
        )?;
        let axis = args.required_axis("axis_index")?;
        let a = &cfg.axes[axis - 1];
        let target = args.required_number("target_position", a.min_deg, a.max_deg, " deg")?;
        let velocity_factor = velocity_factor(&args)?;
        check_position(cfg, axis - 1, target)
            .map_err(|e| args.invalid_value("target_position", target, e))?;
        Ok(Self {
            axis,
            target,
            velocity_factor,
        })
    }

    pub fn sample(&self) -> CommandSample {
        let mut s = sample(CommandKind::MoveAxis);
        s.args[0] = self.axis as f64;
        s.args[1] = self.target;
        s.args[2] = self.velocity_factor;
        s
    }
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
