//! `info`: the `initialization` result (number of axes, version, cycle time, axis limits).
//! It takes no arguments (parsing is in `Command::parse`); [`render`] builds its result.

use crate::result::round;
use mcm_shared::config::RobotConfig;
use mcm_shared::reply::InfoReply;
use serde_json::{Value, json};

/// The initialization result (`info`); `simulated`: the core runs the simulated robot (its
/// state's `STATE_SIMULATED` flag).
pub fn render(cfg: &RobotConfig, info: &InfoReply, simulated: bool) -> Value {
    let axes: Vec<Value> = cfg
        .axes
        .iter()
        .enumerate()
        .map(|(i, a)| {
            json!({
                "axis": i + 1,
                "name": a.name,
                "min_position": a.min_deg,
                "max_position": a.max_deg,
                "max_velocity": a.max_velocity_deg_s,
                "max_acceleration": a.max_acceleration_deg_s2,
                "max_torque": round(a.max_current_a * a.torque_per_amp()),
                "light_barrier": a.calibration.light_barrier_deg.is_some(),
            })
        })
        .collect();
    json!({
        "result_type": "initialization",
        "num_axes": info.num_axes,
        "version": mcm_shared::VERSION,
        "robot": cfg.robot.name,
        "cycle_time": info.period_s,
        "simulated": simulated,
        "axes": axes,
    })
}
