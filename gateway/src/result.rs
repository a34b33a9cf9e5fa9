//! The result objects of the JSON protocol, built from the real-time core's replies and state.
//! Field names follow the manual; extra fields are allowed (clients ignore unknown fields).

use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{Mode, RejectCode, ReplyStatus};
use mcm_shared::sample::{
    AXIS_CALIBRATED, AXIS_ENABLED, AXIS_FAULT, AXIS_I2T_DERATED, AXIS_ONLINE, ErrorRecord, Reply,
    STATE_ALL_CALIBRATED, STATE_ESTOP, STATE_NOT_REALTIME, STATE_PVT_STARVED, STATE_SIM_ESTOP,
    STATE_SIMULATED, StateSample,
};
use serde_json::{Value, json};

/// `{"result_type":"generic","error_status":"OK"}`
pub fn ok() -> Value {
    json!({"result_type": "generic", "error_status": "OK"})
}

/// A generic ERROR result with a message.
pub fn error(message: impl Into<String>) -> Value {
    json!({"result_type": "generic", "error_status": "ERROR", "error_message": message.into()})
}

/// The words for a refused or failed reply, prefixed with the command name.
pub fn reply_error(command: &str, reply: &Reply) -> Value {
    let code = RejectCode::try_from(reply.code).unwrap_or(RejectCode::None);
    let status = ReplyStatus::try_from(reply.status).unwrap_or(ReplyStatus::Rejected);
    let verb = if status == ReplyStatus::Failed {
        "failed"
    } else {
        "refused"
    };
    error(format!(
        "{command} {verb}: {}",
        code.describe(reply.axis, &reply.values)
    ))
}

/// The spontaneous ERROR sent to every client when a safety check trips: the check, the axis,
/// the values, the mode it left the robot in, and the flight-recorder file.
pub fn safety_event(ev: &crate::bridge::SafetyEvent) -> Value {
    let mut v = safety_error(&ev.record);
    let mode = Mode::try_from(ev.mode)
        .map(Mode::as_str)
        .unwrap_or("UNKNOWN");
    let file = ev.file.display().to_string();
    v["error_message"] = json!(format!(
        "{}; mode is now {mode}; flight recorder: {file}",
        v["error_message"].as_str().unwrap_or_default()
    ));
    v["flight_recorder"] = json!(file);
    v
}

/// A safety error in words (without the mode and the flight-recorder file).
pub fn safety_error(e: &ErrorRecord) -> Value {
    let code = RejectCode::try_from(e.code).unwrap_or(RejectCode::None);
    let mut v = error(format!(
        "safety check tripped: {}",
        code.describe(e.axis, &e.values)
    ));
    v["check"] = json!(code.as_str());
    if e.axis != 0 {
        v["axis"] = json!(e.axis);
    }
    v
}

fn mode_name(state: &StateSample) -> &'static str {
    Mode::try_from(state.mode)
        .map(Mode::as_str)
        .unwrap_or("UNKNOWN")
}

fn round(x: f64) -> f64 {
    (x * 1e6).round() / 1e6
}

fn six(v: &[f64; 6]) -> Value {
    json!(v.map(round))
}

fn axis_bits(state: &StateSample, bit: u32) -> Value {
    json!(state.axis_flags.map(|f| f & bit != 0))
}

/// A human summary of the hardware for `hardware_status`.
pub fn hardware_status(state: &StateSample) -> String {
    let count = |bit: u32| state.axis_flags.iter().filter(|f| *f & bit != 0).count();
    let mut parts = vec![
        format!("drives online {}/6", count(AXIS_ONLINE)),
        format!("enabled {}/6", count(AXIS_ENABLED)),
    ];
    let faults = count(AXIS_FAULT);
    if faults > 0 {
        parts.push(format!("in fault {faults}"));
    }
    parts.push(format!(
        "emergency stop {}",
        if state.flags & STATE_ESTOP != 0 {
            "PRESSED"
        } else {
            "released"
        }
    ));
    parts.push(format!("calibrated {}/6", count(AXIS_CALIBRATED)));
    let derated = count(AXIS_I2T_DERATED);
    if derated > 0 {
        parts.push(format!("i2t derated {derated}"));
    }
    if state.flags & STATE_NOT_REALTIME != 0 {
        parts.push("cycle NOT real-time".into());
    }
    parts.join(", ")
}

/// The status result.
pub fn status(state: &StateSample, detail: bool) -> Value {
    let t = round(state.t_ns as f64 / 1e9);
    let mut v = json!({
        "result_type": "status",
        "operating_mode": mode_name(state),
        "axis_states": {
            "time": [t, t, t, t, t, t],
            "position": six(&state.position),
            "velocity": six(&state.velocity),
            "acceleration": six(&state.acceleration),
            "current": six(&state.current),
        },
    });
    if detail {
        v["hardware_status"] = json!(hardware_status(state));
        let tm = &state.timing;
        v["detail"] = json!({
            "cycle": state.seq,
            "calibrated": axis_bits(state, AXIS_CALIBRATED),
            "all_calibrated": state.flags & STATE_ALL_CALIBRATED != 0,
            "measured_position": six(&state.measured_position),
            "commanded_position": six(&state.commanded_position),
            "following_error": six(&state.following_error),
            "i2t": six(&state.i2t),
            "i2t_derated": axis_bits(state, AXIS_I2T_DERATED),
            "drive_online": axis_bits(state, AXIS_ONLINE),
            "drive_enabled": axis_bits(state, AXIS_ENABLED),
            "drive_fault": axis_bits(state, AXIS_FAULT),
            "emergency_stop": state.flags & STATE_ESTOP != 0,
            "pvt_queue": {
                "queued": state.pvt_queued,
                "capacity": state.pvt_capacity,
                "starved": state.flags & STATE_PVT_STARVED != 0,
            },
            "timing": {
                "period_s": tm.period_ns as f64 / 1e9,
                "overruns": tm.overruns,
                "latency_p50_us": tm.latency_p50_ns as f64 / 1e3,
                "latency_p99_us": tm.latency_p99_ns as f64 / 1e3,
                "latency_max_us": tm.latency_max_ns as f64 / 1e3,
                "work_max_us": tm.work_max_ns as f64 / 1e3,
                "realtime": state.flags & STATE_NOT_REALTIME == 0,
            },
        });
    }
    v
}

/// The move_all result from the reply values.
pub fn move_all(reply: &Reply) -> Value {
    let v = &reply.values;
    json!({
        "result_type": "move_all",
        "velocities": [round(v[0]), round(v[1]), round(v[2]), round(v[3]), round(v[4]), round(v[5])],
        "longest": v[6] as u32,
        "max_time_to_target": round(v[7]),
    })
}

/// The initialization result (`info`): number of axes and cycle time from the reply, whether
/// the robot is simulated from the state sample's `STATE_SIMULATED` flag.
pub fn initialization(cfg: &RobotConfig, reply: &Reply, state: &StateSample) -> Value {
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
        "num_axes": reply.values[0] as u32,
        "version": mcm_shared::VERSION,
        "robot": cfg.robot.name,
        "cycle_time": reply.values[1],
        "simulated": state.flags & STATE_SIMULATED != 0,
        "axes": axes,
    })
}

/// The sim result: ground truth of the simulated arm.
pub fn sim(state: &StateSample) -> Value {
    json!({
        "result_type": "sim",
        "true_position": six(&state.sim_true_position),
        "true_velocity": six(&state.sim_true_velocity),
        "emergency_stop": state.flags & STATE_SIM_ESTOP != 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_has_the_manual_fields() {
        let s = StateSample {
            mode: Mode::Hold.to_wire(),
            position: [1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
            ..StateSample::default()
        };
        let v = status(&s, false);
        assert_eq!(v["result_type"], "status");
        assert_eq!(v["operating_mode"], "HOLD");
        for field in ["time", "position", "velocity", "acceleration", "current"] {
            assert_eq!(
                v["axis_states"][field].as_array().unwrap().len(),
                6,
                "{field}"
            );
        }
        assert!(v.get("hardware_status").is_none());
        let d = status(&s, true);
        assert!(
            d["hardware_status"]
                .as_str()
                .unwrap()
                .contains("drives online 0/6")
        );
        assert_eq!(d["detail"]["calibrated"].as_array().unwrap().len(), 6);
    }

    #[test]
    fn info_says_simulated_from_the_state_flag() {
        let cfg = RobotConfig::prob2_default();
        let r = Reply {
            values: [6.0, 0.005, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            ..Reply::default()
        };
        let mut s = StateSample::default();
        let real = initialization(&cfg, &r, &s);
        assert_eq!(real["simulated"], false, "values[2] is not read: {real}");
        assert_eq!(real["num_axes"], 6);
        assert_eq!(real["cycle_time"], 0.005);
        s.flags |= STATE_SIMULATED;
        assert_eq!(initialization(&cfg, &r, &s)["simulated"], true);
    }

    #[test]
    fn reply_errors_are_words() {
        let r = Reply {
            status: ReplyStatus::Rejected.to_wire(),
            code: RejectCode::WrongMode.to_wire(),
            values: [
                Mode::Off.to_wire() as f64,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
            ],
            ..Reply::default()
        };
        assert_eq!(
            reply_error("release", &r)["error_message"],
            "release refused: not allowed in mode OFF"
        );
    }

    #[test]
    fn move_all_result() {
        let r = Reply {
            values: [10.0, 20.0, 0.0, 0.0, 0.0, 30.0, 6.0, 1.5],
            ..Reply::default()
        };
        let v = move_all(&r);
        assert_eq!(v["longest"], 6);
        assert_eq!(v["max_time_to_target"], 1.5);
        assert_eq!(v["velocities"].as_array().unwrap().len(), 6);
    }
}
