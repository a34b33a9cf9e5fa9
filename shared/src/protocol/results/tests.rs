use super::*;
use crate::command::Axis;
use crate::config::RobotConfig;
use crate::reply::{CalibrationFailure, Reason};
use serde_json::json;

fn status(s: &StateSample, detail: bool) -> Value {
    Answer::Status(Box::new(Status::from_state(s, detail).unwrap())).to_value()
}

fn reply_error(kind: CommandKind, outcome: &Outcome) -> Value {
    Answer::Generic(Generic::reply_error(kind, outcome)).to_value()
}

fn safety_error(e: &SafetyError) -> Value {
    Answer::Generic(Generic::safety_error(e)).to_value()
}

fn last_error(r: &ErrorRecord) -> Option<Value> {
    Generic::last_error(r).map(|g| Answer::Generic(g).to_value())
}

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
fn status_has_the_cartesian_state_only_when_the_sample_has_one() {
    let tcp = TcpState {
        position: [0.1, -0.2, 0.812_345_678],
        orientation: [0.0, 0.6, 0.0, 0.8],
        linear_velocity: [0.01, 0.0, -0.02],
        angular_velocity: [0.0, 12.5, 0.0],
    };
    let mut s = StateSample {
        flags: STATE_ALL_CALIBRATED,
        cartesian: tcp,
        ..StateSample::default()
    };
    assert!(status(&s, false).get("cartesian_state").is_none());
    s.flags |= crate::sample::STATE_CARTESIAN;
    let v = status(&s, false);
    assert_eq!(
        v["cartesian_state"],
        json!({
            "position": [0.1, -0.2, 0.812346],
            "orientation": [0.0, 0.6, 0.0, 0.8],
            "linear_velocity": [0.01, 0.0, -0.02],
            "angular_velocity": [0.0, 12.5, 0.0],
        })
    );
    let Answer::Status(read) = Answer::from_value(&v).unwrap() else {
        panic!("not a status: {v}");
    };
    assert_eq!(read.cartesian_state, Some(CartesianState::from(&tcp)));
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
fn status_detail_shows_the_bus_counters() {
    let s = StateSample {
        bus: crate::sample::BusCounters {
            bad_frames: 1,
            frames_dropped: 2,
            events_dropped: 3,
            bus_errors: 4,
        },
        ..StateSample::default()
    };
    let bus = &status(&s, true)["detail"]["bus"];
    assert_eq!(bus["bad_frames"], 1);
    assert_eq!(bus["frames_dropped"], 2);
    assert_eq!(bus["events_dropped"], 3);
    assert_eq!(bus["bus_errors"], 4);
    assert_eq!(bus.as_object().unwrap().len(), 4);
}

#[test]
fn status_detail_shows_the_tool_as_set_tool_takes_it() {
    let tool = crate::tool::Tool::new(
        crate::tool::Tcp {
            position: [0.0, 0.0, 0.15],
            orientation: [0.0, 0.0, 0.0, 1.0],
        },
        2.0,
        [0.0, 0.0, 0.06],
        Some([0.01, 0.01, 0.005, 0.0, 0.0, 0.0]),
    )
    .unwrap();
    let s = StateSample {
        tool: (&tool).into(),
        ..StateSample::default()
    };
    let shown = &status(&s, true)["detail"]["tool"];
    assert_eq!(
        *shown,
        json!({
            "tcp": {"position": [0.0, 0.0, 0.15], "orientation": [0.0, 0.0, 0.0, 1.0]},
            "mass": 2.0,
            "center_of_mass": [0.0, 0.0, 0.06],
            "inertia": [0.01, 0.01, 0.005, 0.0, 0.0, 0.0]
        })
    );
    // What it shows is what `set_tool` takes.
    let line = json!({"command": "set_tool", "arguments": shown});
    let cmd = crate::protocol::Command::from_value(&line, &RobotConfig::prob2_default()).unwrap();
    assert_eq!(
        cmd,
        crate::protocol::Command::SetTool(crate::command::SetTool { tool })
    );
}

#[test]
fn status_detail_shows_the_tail_the_window_and_the_budget() {
    use crate::sample::{CycleTiming, LatencyFigures};
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
        reply_error(CommandKind::Release, &refused)["error_message"],
        "release refused: not allowed in mode OFF"
    );
    assert_eq!(
        reply_error(CommandKind::Release, &refused)["outcome"],
        "refused"
    );
    let failed = Outcome::Failed(Reason::CalibrationFailed {
        axis: Axis::new(2).unwrap(),
        cause: CalibrationFailure::DriveLost,
    });
    assert_eq!(
        reply_error(CommandKind::Calibrate, &failed)["error_message"],
        "calibrate failed: calibration of axis 2 failed: its drive stopped answering"
    );
    assert_eq!(
        reply_error(CommandKind::Calibrate, &failed)["outcome"],
        "failed"
    );
}

#[test]
fn every_outcome_reads_back_by_its_wire_name() {
    let names: Vec<&str> = ErrorOutcome::ALL.iter().map(|o| o.as_str()).collect();
    assert_eq!(names, ["refused", "failed", "invalid", "unknown"]);
    for o in ErrorOutcome::ALL {
        assert_eq!(ErrorOutcome::from_name(o.as_str()), Some(o));
        assert_eq!(o.to_string(), o.as_str());
        let g = Generic::answer_error(o, ErrorCode::Busy, "x").answering("set_torques");
        let v = Answer::Generic(g.clone()).to_value();
        assert_eq!(v["outcome"], o.as_str(), "{v}");
        assert_eq!(v["command"], "set_torques", "{v}");
        let Answer::Generic(back) = Answer::from_value(&v).unwrap() else {
            panic!("{v}")
        };
        assert_eq!(back, g);
        assert_eq!(back.outcome(), Some(o));
    }
    // An outcome of a newer MCM version reads, as no outcome this version knows.
    let v = json!({"result_type":"generic","error_status":"ERROR","outcome":"postponed"});
    let Answer::Generic(g) = Answer::from_value(&v).unwrap() else {
        panic!("{v}")
    };
    assert_eq!(g.outcome(), None);
    assert_eq!(ErrorOutcome::from_name("Refused"), None);
}

/// `docs/protocol.md` lists every outcome with its meaning as [`ErrorOutcome::meaning`] words
/// it.
#[test]
fn the_protocol_document_lists_every_outcome() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/protocol.md");
    let doc = std::fs::read_to_string(&path).expect("docs/protocol.md");
    for o in ErrorOutcome::ALL {
        let row = format!("| `{}` | {} |", o.as_str(), o.meaning());
        assert!(doc.contains(&row), "docs/protocol.md lacks the row {row}");
    }
}

#[test]
fn a_line_refused_before_it_became_a_command_names_the_command_it_names() {
    let cfg = RobotConfig::prob2_default();
    let refused = |line: &str| {
        let e = crate::protocol::Command::from_json(line, &cfg).unwrap_err();
        Answer::Generic(Generic::invalid_line(&e)).to_value()
    };
    let v = refused(r#"{"command":"set_torques","arguments":{"torques":[1,2]}}"#);
    assert_eq!(v["command"], "set_torques", "{v}");
    assert_eq!(v["outcome"], "invalid", "{v}");
    for line in [r#"{"command":"stauts"}"#, "{\"arguments\":{}}", "[1]"] {
        let v = refused(line);
        assert!(v.get("command").is_none(), "{line}: {v}");
        assert_eq!(v["outcome"], "invalid", "{line}: {v}");
    }
    // OK answers nothing more.
    let ok = Answer::ok().answering("hold").to_value();
    assert_eq!(ok, json!({"result_type":"generic","error_status":"OK"}));
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
    assert_eq!(
        v["error_code"], v["check"],
        "a safety error's code is its check"
    );
    assert_eq!(last_error(&e.encode()), Some(v));
    assert_eq!(last_error(&ErrorRecord::default()), None);
    let unknown = ErrorRecord {
        code: 99,
        ..e.encode()
    };
    let unreadable = last_error(&unknown).unwrap();
    assert_eq!(unreadable["error_code"], "version_mismatch");
    let text = unreadable["error_message"].to_string();
    assert!(
        text.contains("cannot be read (reject code 99 is not known") && !text.contains("no error"),
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
    let v = Answer::MoveAll(MoveAllResult::from(&plan)).to_value();
    assert_eq!(v["longest"], 6);
    assert_eq!(v["max_time_to_target"], 1.5);
    assert_eq!(v["velocities"], json!([10.0, 20.0, 0.0, 0.0, 0.0, 30.0]));
}

/// The `payload` result carries the core's figures by the contract's names, rounded as every
/// figure is, and reads back.
#[test]
fn payload_result() {
    let reply = crate::reply::PayloadReply {
        mass_kg: 2.012_345_678,
        center_of_mass_m: [0.001, -0.002, 0.059_876_543_21],
        residual_nm: 0.137,
    };
    let v = Answer::Payload(PayloadResult::from(&reply)).to_value();
    assert_eq!(v["result_type"], "payload");
    assert_eq!(v["mass"], 2.012346);
    assert_eq!(v["center_of_mass"], json!([0.001, -0.002, 0.059877]));
    assert_eq!(v["residual"], 0.137);
    assert!(matches!(Answer::from_value(&v), Ok(Answer::Payload(_))));
}

#[test]
fn info_takes_simulated_from_the_state() {
    let cfg = RobotConfig::prob2_default();
    let info = InfoReply {
        num_axes: 6,
        period_s: 0.005,
    };
    let v = Answer::Initialization(Info::new(&cfg, &info, true)).to_value();
    assert_eq!(
        (v["num_axes"].as_u64(), v["cycle_time"].as_f64()),
        (Some(6), Some(0.005))
    );
    assert_eq!(v["simulated"], true);
    assert_eq!(
        Answer::Initialization(Info::new(&cfg, &info, false)).to_value()["simulated"],
        false
    );
}

/// One result of every `result_type` (the match makes a new one fail to compile until it is
/// added here).
fn one_of_each() -> Vec<Answer> {
    let state = StateSample::default();
    let info = InfoReply {
        num_axes: 6,
        period_s: 0.005,
    };
    let each = vec![
        Answer::ok(),
        Answer::error(ErrorCode::Busy, "move_all refused: x"),
        Answer::Status(Box::new(Status::from_state(&state, false).unwrap())),
        Answer::Initialization(Info::new(&RobotConfig::prob2_default(), &info, true)),
        Answer::MoveAll(MoveAllResult {
            velocities: [1.0; 6],
            longest: 2,
            max_time_to_target: 0.5,
        }),
        Answer::MoveLinear(MoveLinearResult {
            duration: 0.5,
            joint_target: [1.0; 6],
        }),
        Answer::Sim(SimResult::from_state(&state)),
        Answer::InverseKinematics(InverseKinematicsResult::new([[1.0; 6], [2.0; 6]])),
        Answer::Payload(PayloadResult {
            mass: 2.0,
            center_of_mass: [0.0, 0.0, 0.06],
            residual: 0.1,
        }),
    ];
    for a in &each {
        match a {
            Answer::Generic(_)
            | Answer::Status(_)
            | Answer::Initialization(_)
            | Answer::MoveAll(_)
            | Answer::MoveLinear(_)
            | Answer::Sim(_)
            | Answer::InverseKinematics(_)
            | Answer::Payload(_) => {}
        }
    }
    each
}

/// `Answer::result_type` is the `result_type` the JSON carries, and `Success` names the same
/// words: what a command's definition says it answers and the result a client waits for cannot
/// drift apart.
#[test]
fn every_result_type_is_the_one_a_success_names() {
    use crate::protocol::Success;
    let each = one_of_each();
    for a in &each {
        assert_eq!(a.to_value()["result_type"], a.result_type(), "{a:?}");
    }
    let successes = [
        Success::Ok,
        Success::Status,
        Success::Nothing,
        Success::Initialization,
        Success::MoveAll,
        Success::MoveLinear,
        Success::Sim,
        Success::InverseKinematics,
        Success::Payload,
    ];
    let mut named = std::collections::BTreeSet::new();
    for s in successes {
        match s {
            Success::Ok
            | Success::Status
            | Success::Nothing
            | Success::Initialization
            | Success::MoveAll
            | Success::MoveLinear
            | Success::Sim
            | Success::InverseKinematics
            | Success::Payload => {}
        }
        let answering: Vec<&Answer> = each.iter().filter(|a| s.answers(a)).collect();
        match s.result_type() {
            None => assert!(answering.is_empty(), "{s:?} answers {answering:?}"),
            Some(t) => {
                // Exactly one of each: `generic` OK answers `Success::Ok`, an ERROR nothing.
                assert_eq!(answering.len(), 1, "{s:?} answers {answering:?}");
                assert_eq!(answering[0].result_type(), t, "{s:?}");
                named.insert(t);
            }
        }
    }
    let types: std::collections::BTreeSet<_> = each.iter().map(Answer::result_type).collect();
    assert_eq!(named, types, "every result_type is answered by one Success");
    assert!(!Success::Ok.answers(&Answer::error(ErrorCode::Busy, "x")));
}

/// A line that is no result of this version is refused naming what is wrong and the value.
#[test]
fn unreadable_results_are_typed_errors_naming_the_value() {
    assert!(matches!(
        Answer::from_value(&json!({})),
        Err(ReadError::NoResultType)
    ));
    let e = Answer::from_value(&json!({"result_type": 7})).unwrap_err();
    assert!(matches!(&e, ReadError::ResultTypeNotString { value } if value == "7"));
    assert_eq!(e.to_string(), "result_type is 7, not a string");
    let e = Answer::from_value(&json!({"result_type": "telemetry"})).unwrap_err();
    let ReadError::Unreadable { result_type, .. } = &e else {
        panic!("{e:?}")
    };
    assert_eq!(result_type, "telemetry");
    assert!(
        e.to_string()
            .starts_with("a `telemetry` result that does not read: "),
        "{e}"
    );
    let mut status = status(&StateSample::default(), false);
    status["operating_mode"] = "FLYING".into();
    let e = Answer::from_value(&status).unwrap_err();
    assert!(e.to_string().contains("FLYING is not a known mode"), "{e}");
}

#[test]
fn a_state_in_an_unknown_mode_names_the_mode_and_the_known_ones() {
    let s = StateSample {
        mode: 99,
        ..StateSample::default()
    };
    let e = Status::from_state(&s, false).unwrap_err();
    assert_eq!(e, UnknownMode { value: 99 });
    let text = e.to_string();
    assert!(
        text.contains("operating mode 99, which this MCM version does not know"),
        "{text}"
    );
    assert!(text.contains("0 OFF, 1 ERROR"), "{text}");
}

proptest::proptest! {
    /// Every reason of the core, refused, failed or tripped, reaches a client with its code:
    /// the code of the reason (a safety error's `error_code` equal to its `check`), which a
    /// client reads back as the same code.
    #[test]
    fn every_reason_carries_its_code(reason in crate::reply::tests::reason()) {
        let name = reason.code().as_str();
        for (outcome, ended) in [
            (Outcome::Refused(reason), ErrorOutcome::Refused),
            (Outcome::Failed(reason), ErrorOutcome::Failed),
        ] {
            let v = reply_error(CommandKind::MoveAxis, &outcome);
            proptest::prop_assert_eq!(v["error_code"].as_str(), Some(name));
            proptest::prop_assert_eq!(v["outcome"].as_str(), Some(ended.as_str()));
            let back = Answer::from_value(&v).unwrap();
            let Answer::Generic(g) = back else { panic!("{v}") };
            proptest::prop_assert_eq!(g.code(), Some(reason.error_code()));
            proptest::prop_assert_eq!(g.outcome(), Some(ended));
        }
        let e = SafetyError { seq: 1, cycle: 1, unix_ns: 0, reason };
        let v = safety_error(&e);
        proptest::prop_assert_eq!(v["error_code"].as_str(), Some(name));
        proptest::prop_assert_eq!(&v["error_code"], &v["check"]);
        proptest::prop_assert!(v.get("outcome").is_none() && v.get("command").is_none(), "{}", v);
    }
}
