//! The result objects of the JSON protocol shared by several commands (`generic`, `status`, the
//! spontaneous errors), built from the real-time core's typed answers
//! ([`mcm_shared::reply`]) and state. Field names follow the manual; extra fields are allowed
//! (clients ignore unknown fields).

use mcm_shared::command::DecodeError;
use mcm_shared::mode::{CommandKind, Mode};
use mcm_shared::reply::{Outcome, SafetyError};
use mcm_shared::sample::{
    AXIS_CALIBRATED, AXIS_ENABLED, AXIS_FAULT, AXIS_I2T_DERATED, AXIS_ONLINE, ErrorRecord,
    STATE_ALL_CALIBRATED, STATE_ESTOP, STATE_NOT_REALTIME, STATE_PVT_STARVED, STATE_SHUTTING_DOWN,
    StateSample,
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

/// The words for a refused or failed command, prefixed with the command name (a command
/// that was done is [`ok`]). A value of an argument outside its range reads exactly as the
/// gateway's own refusal of it (`move_axis: argument "target_position" = 175 is not allowed;
/// expected ...`), whichever side refused.
pub fn reply_error(command: &str, outcome: &Outcome) -> Value {
    let kind = CommandKind::ALL.iter().find(|k| k.as_str() == command);
    match outcome {
        Outcome::Refused(reason) => match kind.and_then(|k| reason.argument(*k)) {
            Some(arg) => error(format!("{command}: {arg}")),
            None => error(format!("{command} refused: {reason}")),
        },
        Outcome::Failed(reason) => error(format!("{command} failed: {reason}")),
        Outcome::Done(_) => ok(),
    }
}

/// The spontaneous ERROR sent to every client when a safety check trips: the check, the axis,
/// the values, the mode it left the robot in, and the flight-recorder file.
pub fn safety_event(ev: &crate::bridge::SafetyEvent) -> Value {
    let mut v = match &ev.error {
        Ok(e) => safety_error(e),
        Err(e) => unreadable_safety_error(e),
    };
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
pub fn safety_error(e: &SafetyError) -> Value {
    let mut v = error(format!("safety check tripped: {}", e.reason));
    v["check"] = json!(e.reason.code().as_str());
    if let Some(axis) = e.reason.axis() {
        v["axis"] = json!(axis.number());
    }
    v
}

/// A safety error whose record this gateway cannot read (a core of another MCM version).
pub fn unreadable_safety_error(e: &DecodeError) -> Value {
    error(format!(
        "safety check tripped, but its record cannot be read ({e}); mcm-rt and the gateway are \
         from different MCM versions: rebuild both from the same version"
    ))
}

/// The safety error a state reports in words; `None` when there was none since start.
pub fn last_error(record: &ErrorRecord) -> Option<Value> {
    match SafetyError::decode(record) {
        Ok(e) => e.as_ref().map(safety_error),
        Err(e) => Some(unreadable_safety_error(&e)),
    }
}

fn mode_name(state: &StateSample) -> &'static str {
    Mode::try_from(state.mode)
        .map(Mode::as_str)
        .unwrap_or("UNKNOWN")
}

/// A figure rounded to 6 decimals for the JSON results.
pub(crate) fn round(x: f64) -> f64 {
    (x * 1e6).round() / 1e6
}

/// Six figures, rounded.
pub(crate) fn six(v: &[f64; 6]) -> Value {
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
            "shutting_down": state.flags & STATE_SHUTTING_DOWN != 0,
            "pvt_queue": {
                "queued": state.pvt_queued,
                "capacity": state.pvt_capacity,
                "starved": state.flags & STATE_PVT_STARVED != 0,
            },
            "timing": {
                "period_s": tm.period_ns as f64 / 1e9,
                "overruns": tm.overruns,
                "latency_p50_us": tm.since_start.p50_ns as f64 / 1e3,
                "latency_p99_us": tm.since_start.p99_ns as f64 / 1e3,
                "latency_max_us": tm.since_start.max_ns as f64 / 1e3,
                "latency_p99_9_us": tm.since_start.p99_9_ns as f64 / 1e3,
                "latency_p99_99_us": tm.since_start.p99_99_ns as f64 / 1e3,
                "cycles": tm.since_start.cycles,
                "recent": {
                    "window_s": tm.recent_window_ns as f64 / 1e9,
                    "cycles": tm.recent.cycles,
                    "latency_p50_us": tm.recent.p50_ns as f64 / 1e3,
                    "latency_p99_us": tm.recent.p99_ns as f64 / 1e3,
                    "latency_p99_9_us": tm.recent.p99_9_ns as f64 / 1e3,
                    "latency_p99_99_us": tm.recent.p99_99_ns as f64 / 1e3,
                    "latency_max_us": tm.recent.max_ns as f64 / 1e3,
                },
                "work_max_us": tm.work_max_ns as f64 / 1e3,
                "work_budget_us": tm.work_budget_ns as f64 / 1e3,
                "over_budget": tm.over_budget,
                "realtime": state.flags & STATE_NOT_REALTIME == 0,
            },
            "ipc": {
                "command_receive_errors": state.command_receive_errors,
            },
        });
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use mcm_shared::command::Axis;
    use mcm_shared::config::RobotConfig;
    use mcm_shared::reply::{CalibrationFailure, InfoReply, MoveAllPlan, Reason};

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
    fn status_detail_shows_the_receive_errors() {
        let s = StateSample {
            command_receive_errors: 3,
            ..StateSample::default()
        };
        assert_eq!(
            status(&s, true)["detail"]["ipc"]["command_receive_errors"],
            3
        );
    }

    #[test]
    fn status_detail_shows_the_tail_the_window_and_the_budget() {
        use mcm_shared::sample::{CycleTiming, LatencyFigures};
        let timing = CycleTiming {
            since_start: LatencyFigures {
                p99_9_ns: 300_000,
                p99_99_ns: 640_000,
                cycles: 12_000,
                ..LatencyFigures::default()
            },
            recent: LatencyFigures {
                p50_ns: 58_000,
                max_ns: 700_000,
                cycles: 2_000,
                ..LatencyFigures::default()
            },
            recent_window_ns: 10_000_000_000,
            work_budget_ns: 2_500_000,
            over_budget: 4,
            ..CycleTiming::default()
        };
        let s = StateSample {
            timing,
            ..StateSample::default()
        };
        let t = &status(&s, true)["detail"]["timing"];
        assert_eq!(t["latency_p99_9_us"], 300.0);
        assert_eq!(t["latency_p99_99_us"], 640.0);
        assert_eq!(t["cycles"], 12_000);
        assert_eq!(t["recent"]["latency_p50_us"], 58.0);
        assert_eq!(t["recent"]["latency_max_us"], 700.0);
        assert_eq!(t["recent"]["window_s"], 10.0);
        assert_eq!(t["recent"]["cycles"], 2_000);
        assert_eq!(t["work_budget_us"], 2500.0);
        assert_eq!(t["over_budget"], 4);
    }

    #[test]
    fn reply_errors_are_words() {
        let refused = Outcome::Refused(Reason::WrongMode { mode: Mode::Off });
        assert_eq!(
            reply_error("release", &refused)["error_message"],
            "release refused: not allowed in mode OFF"
        );
        let failed = Outcome::Failed(Reason::CalibrationFailed {
            axis: Axis::new(2).unwrap(),
            cause: CalibrationFailure::DriveLost,
        });
        assert_eq!(
            reply_error("calibrate", &failed)["error_message"],
            "calibrate failed: calibration of axis 2 failed: its drive stopped answering"
        );
    }

    #[test]
    fn safety_errors_name_the_check_and_the_axis() {
        let e = SafetyError {
            seq: 1,
            cycle: 10,
            unix_ns: 0,
            reason: Reason::FollowingError {
                axis: Axis::new(3).unwrap(),
                error_deg: 2.5,
                band_deg: 2.0,
            },
        };
        let v = safety_error(&e);
        assert_eq!(
            v["error_message"],
            "safety check tripped: following error: axis 3 is 2.500 deg away from its commanded \
             position, band 2.000 deg"
        );
        assert_eq!(
            (v["check"].as_str(), v["axis"].as_u64()),
            (Some("following_error"), Some(3))
        );
        assert_eq!(last_error(&e.encode()), Some(v));
        assert_eq!(last_error(&ErrorRecord::default()), None);
        let unknown = ErrorRecord {
            code: 99,
            ..e.encode()
        };
        let text = last_error(&unknown).unwrap()["error_message"].to_string();
        assert!(
            text.contains("cannot be read (reject code 99 is not known")
                && !text.contains("no error"),
            "{text}"
        );
    }

    #[test]
    fn move_all_result() {
        let plan = MoveAllPlan {
            velocities_deg_s: [10.0, 20.0, 0.0, 0.0, 0.0, 30.0],
            longest: Axis::new(6).unwrap(),
            duration_s: 1.5,
        };
        let v = crate::cmd::move_all::render(&plan);
        assert_eq!(v["longest"], 6);
        assert_eq!(v["max_time_to_target"], 1.5);
        assert_eq!(v["velocities"], json!([10.0, 20.0, 0.0, 0.0, 0.0, 30.0]));
    }

    #[test]
    fn info_takes_simulated_from_the_state() {
        let cfg = RobotConfig::prob2_default();
        let info = InfoReply {
            num_axes: 6,
            period_s: 0.005,
        };
        let v = crate::cmd::info::render(&cfg, &info, true);
        assert_eq!(
            (v["num_axes"].as_u64(), v["cycle_time"].as_f64()),
            (Some(6), Some(0.005))
        );
        assert_eq!(v["simulated"], true);
        assert_eq!(
            crate::cmd::info::render(&cfg, &info, false)["simulated"],
            false
        );
    }
}
