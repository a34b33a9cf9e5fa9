//! `move_all`: move all axes to target positions, time-synchronised (all start and arrive
//! together). Replies with the `move_all` result.

use super::move_axis::velocity_factor;
use super::{check_position, sample};
use crate::args::{Args, CommandError};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::CommandKind;
use mcm_shared::sample::CommandSample;
use serde_json::Value;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveAll {
    /// [deg]
    pub targets: [f64; 6],
    pub velocity_factor: f64,
}

impl MoveAll {
    pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        let args = Args::new(
            "move_all",
            arguments,
            &["target_positions", "velocity_factor"],
        )?;
        let targets = args.required_six("target_positions", "positions [deg]", |i, x| {
            check_position(cfg, i, x)
        })?;
        Ok(Self {
            targets,
            velocity_factor: velocity_factor(&args)?,
        })
    }

    pub fn sample(&self) -> CommandSample {
        let mut s = sample(CommandKind::MoveAll);
        s.args[..6].copy_from_slice(&self.targets);
        s.args[6] = self.velocity_factor;
        s
    }
}
