//! `move_all`: move all axes to target positions, time-synchronised (all start and arrive
//! together). Replies with the `move_all` result.

use super::move_axis::velocity_factor;
use crate::args::{Args, CommandError};
use mcm_shared::command::MoveAll;
use mcm_shared::config::RobotConfig;
use mcm_shared::ranges::Arg;
use mcm_shared::reply::MoveAllPlan;
use serde_json::{Value, json};

/// Parse the arguments of `move_all`, each target within its axis's reachable range.
pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<MoveAll, CommandError> {
    let args = Args::new(
        "move_all",
        arguments,
        &["target_positions", "velocity_factor"],
    )?;
    let targets_deg = args.required_ranged_six(Arg::TargetPositions, cfg)?;
    Ok(MoveAll {
        targets_deg,
        velocity_factor: velocity_factor(&args)?,
    })
}

/// The move_all result from the plan of the core.
pub fn render(plan: &MoveAllPlan) -> Value {
    json!({
        "result_type": "move_all",
        "velocities": crate::result::six(&plan.velocities_deg_s),
        "longest": plan.longest.number(),
        "max_time_to_target": crate::result::round(plan.duration_s),
    })
}
