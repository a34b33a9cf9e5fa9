//! `sim`: fault injection into the simulated robot (refused on real hardware by the real-time
//! core). Any combination of arguments; the reply is a `sim` result with the ground truth.

use crate::args::{Args, CommandError};
use mcm_shared::command::SimCommand;
use mcm_shared::config::RobotConfig;
use mcm_shared::ranges::Arg;
use mcm_shared::sample::{STATE_SIM_ESTOP, StateSample};
use serde_json::{Value, json};

/// Parse the arguments of `sim`; those not given change nothing.
pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<SimCommand, CommandError> {
    let args = Args::new(
        "sim",
        arguments,
        &[
            "emergency_stop",
            "disconnect_axis",
            "reconnect_axis",
            "block_axis",
            "unblock_axis",
            "external_torques",
            "power_cycle",
        ],
    )?;
    Ok(SimCommand {
        emergency_stop: args.boolean("emergency_stop")?,
        disconnect_axis: args.axis("disconnect_axis")?,
        reconnect_axis: args.axis("reconnect_axis")?,
        block_axis: args.axis("block_axis")?,
        unblock_axis: args.axis("unblock_axis")?,
        external_torques_nm: args.ranged_six(Arg::ExternalTorques, cfg)?,
        power_cycle: args.boolean("power_cycle")?.unwrap_or(false),
    })
}

/// The sim result: ground truth of the simulated arm.
pub fn render(state: &StateSample) -> Value {
    json!({
        "result_type": "sim",
        "true_position": crate::result::six(&state.sim_true_position),
        "true_velocity": crate::result::six(&state.sim_true_velocity),
        "emergency_stop": state.flags & STATE_SIM_ESTOP != 0,
    })
}
