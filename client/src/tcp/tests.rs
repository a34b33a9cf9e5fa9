//! The client against a scripted server on a loopback socket: results, events in between,
//! a closed connection and reconnecting.

use super::*;
use serde_json::{Value, json};
use std::io::{BufRead, BufReader};
use std::net::TcpListener;
use std::sync::mpsc;

fn status(mode: &str, t: f64) -> String {
    format!(
        r#"{{"result_type":"status","operating_mode":"{mode}","axis_states":{{"time":[{t},{t},{t},{t},{t},{t}],"position":[0,0,0,0,0,0],"velocity":[0,0,0,0,0,0],"acceleration":[0,0,0,0,0,0],"current":[0,0,0,0,0,0]}}}}"#
    )
}

/// The result line the gateway writes for a command line it refuses itself.
fn refusal_line(json: &str) -> String {
    let cfg = mcm_shared::config::RobotConfig::prob2_default();
    let e = Command::from_json(json, &cfg).unwrap_err();
    Answer::Generic(mcm_shared::protocol::results::Generic::invalid_line(&e))
        .to_value()
        .to_string()
}

/// The result line the gateway writes for the core's refusal of a `kind` request.
fn core_refusal_line(
    kind: mcm_shared::mode::CommandKind,
    reason: mcm_shared::reply::Reason,
) -> String {
    let outcome = mcm_shared::reply::Outcome::Refused(reason);
    let g = mcm_shared::protocol::results::Generic::reply_error(kind, &outcome);
    Answer::Generic(g.answering(kind.as_str()))
        .to_value()
        .to_string()
}

/// A server that answers the n-th line it reads with `script[n]` (several lines, or none),
/// and reports every line read on the channel. Connections are served one after the other.
fn server(script: Vec<Vec<String>>) -> (String, mpsc::Receiver<String>) {
    let l = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = l.local_addr().unwrap().to_string();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let mut script = script.into_iter();
        for conn in l.incoming() {
            let conn = conn.unwrap();
            let mut w = conn.try_clone().unwrap();
            for line in BufReader::new(conn).lines() {
                let Ok(line) = line else { break };
                let _ = tx.send(line);
                match script.next() {
                    Some(answer) if answer == ["CLOSE"] => break,
                    Some(answer) => {
                        for a in answer {
                            w.write_all(format!("{a}\n").as_bytes()).unwrap();
                        }
                    }
                    None => return,
                }
            }
        }
    });
    (addr, rx)
}

/// The spontaneous error the gateway sends when the velocity check of axis 3 trips.
fn safety_line() -> String {
    use mcm_shared::protocol::results::Generic;
    use mcm_shared::reply::{Reason, SafetyError};
    let e = SafetyError {
        seq: 1,
        cycle: 100,
        unix_ns: 0,
        reason: Reason::VelocityLimit {
            axis: mcm_shared::command::Axis::new(3).unwrap(),
            velocity_deg_s: 200.0,
            limit_deg_s: 150.0,
        },
    };
    let g = Generic::safety_event(
        &Ok(e),
        Mode::Error.to_wire(),
        "/tmp/mcm-flight.csv".as_ref(),
    );
    Answer::Generic(g).to_value().to_string()
}

#[test]
fn ticks_and_errors_between_results_become_events() {
    let ok = r#"{"result_type":"generic","error_status":"OK"}"#.to_string();
    let (addr, seen) = server(vec![
        vec![status("TORQUE_CONTROL", 1.0)],
        // set_torques: a refusal, later.
        vec![refusal_line(
            r#"{"command":"set_torques","arguments":{"torques":[900,0,0,0,0,0]}}"#,
        )],
        // hold: two ticks of the session, a safety error, then hold's own status.
        vec![
            status("TORQUE_CONTROL", 1.1),
            status("TORQUE_CONTROL", 1.2),
            safety_line(),
            status("HOLD", 1.3),
        ],
        vec![ok.clone()],
    ]);
    let mut c = TcpClient::connect(&addr).unwrap();
    let o = TorqueOptions {
        dt_status_s: Some(0.1),
        ..TorqueOptions::default()
    };
    assert_eq!(c.torque_control(o).unwrap().mode, Mode::TorqueControl);
    c.set_torques([900.0, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
    let held = c.hold().unwrap();
    assert_eq!((held.mode, held.time()), (Mode::Hold, 1.3));
    c.take_control().unwrap();
    let mut events = Vec::new();
    while let Some(e) = c.next_event(Duration::from_millis(50)).unwrap() {
        events.push(e);
    }
    assert_eq!(events.len(), 4, "{events:#?}");
    assert!(
        matches!(&events[0], Event::CommandError(e) if e.code == Some(mcm_shared::error_code::ErrorCode::OutOfRange))
    );
    assert!(matches!(&events[1], Event::Status(s) if s.time() == 1.1));
    assert!(matches!(&events[2], Event::Status(s) if s.time() == 1.2));
    assert!(matches!(
        &events[3],
        Event::SafetyError { axis: Some(3), .. }
    ));
    let sent: Vec<String> = seen.try_iter().collect();
    assert_eq!(sent.len(), 4);
    assert!(sent[0].contains(r#""dt_status":0.1"#), "{}", sent[0]);
    assert!(sent[1].contains(r#""torques":[900.0,0.0"#), "{}", sent[1]);
}

#[test]
fn refusals_carry_command_words_and_code() {
    let (addr, _seen) = server(vec![vec![core_refusal_line(
        mcm_shared::mode::CommandKind::MoveAll,
        mcm_shared::reply::Reason::WrongMode { mode: Mode::Hold },
    )]]);
    let mut c = TcpClient::connect(&addr).unwrap();
    let e = c.move_all([0.0; 6], 0.5).unwrap_err();
    let m = e.mcm().expect("the MCM's error");
    assert_eq!(m.command, "move_all");
    assert_eq!(m.kind, ErrorKind::Refused);
    assert_eq!(m.code, Some(mcm_shared::error_code::ErrorCode::WrongMode));
    assert_eq!(e.to_string(), "move_all refused: not allowed in mode HOLD");
}

#[test]
fn a_closed_connection_fails_the_call_and_reconnect_opens_a_new_one() {
    let ok = r#"{"result_type":"generic","error_status":"OK"}"#.to_string();
    let (addr, seen) = server(vec![
        vec!["CLOSE".into()],
        vec![ok.clone()], // authenticate on the new connection
        vec![ok.clone()], // take_control
        vec!["CLOSE".into()],
        vec![ok.clone()], // authenticate, by reconnect_on_next_call
        vec![ok.clone()],
    ]);
    let mut c = TcpClient::connect(&addr).unwrap();
    c.secret = Some("s3cret".into());
    assert!(matches!(c.take_control(), Err(Error::Closed { .. })));
    assert!(!c.is_connected());
    assert!(matches!(c.take_control(), Err(Error::NotConnected)));
    c.reconnect().unwrap();
    c.take_control().unwrap();
    assert!(matches!(c.release_control(), Err(Error::Closed { .. })));
    c.opts.reconnect_on_next_call = true;
    c.release_control().unwrap();
    let sent: Vec<String> = seen.try_iter().collect();
    let names: Vec<&str> = sent
        .iter()
        .map(|l| {
            let v: Value = serde_json::from_str(l).unwrap();
            match v["command"].as_str().unwrap() {
                "take_control" => "take",
                "release_control" => "release",
                "authenticate" => "auth",
                _ => "?",
            }
        })
        .collect();
    assert_eq!(
        names,
        ["take", "auth", "take", "release", "auth", "release"]
    );
}

#[test]
fn a_result_that_does_not_come_is_a_timeout_naming_the_command() {
    let (addr, _seen) = server(vec![vec![]]);
    let opts = TcpOptions {
        reply_timeout: Duration::from_millis(100),
        ..TcpOptions::default()
    };
    let mut c = TcpClient::connect_with(&addr, opts).unwrap();
    let e = c.info().unwrap_err();
    assert!(
        matches!(&e, Error::Timeout { command, .. } if command == "info"),
        "{e}"
    );
    assert!(!c.is_connected(), "a timed-out call closes its connection");
}

/// A result of another type than the command answers is a protocol error, never taken as the
/// command's result (nor a panic).
#[test]
fn a_result_of_the_wrong_type_is_a_protocol_error() {
    let sim = r#"{"result_type":"sim","true_position":[1,2,3,4,5,6],"true_velocity":[0,0,0,0,0,0],"emergency_stop":false}"#;
    let move_all = r#"{"result_type":"move_all","velocities":[1,2,3,4,5,6],"longest":3,"max_time_to_target":1.5}"#;
    let (addr, _seen) = server(vec![
        vec![sim.into()],
        vec![sim.into()],
        vec![move_all.into()],
        vec![r#"{"result_type":"generic","error_status":"OK"}"#.into()],
    ]);
    let mut c = TcpClient::connect(&addr).unwrap();
    let wrong = |e: Error, command: &str, problem: &str| match e {
        Error::Protocol {
            command: c,
            problem: p,
            ..
        } => assert_eq!((c.as_str(), p.to_string().as_str()), (command, problem)),
        other => panic!("{other}"),
    };
    wrong(
        c.info().unwrap_err(),
        "info",
        "a sim result where initialization was expected",
    );
    wrong(
        c.move_all([0.0; 6], 0.5).unwrap_err(),
        "move_all",
        "a sim result where move_all was expected",
    );
    wrong(
        c.sim(SimCommand::default()).unwrap_err(),
        "sim",
        "a move_all result where sim was expected",
    );
    wrong(
        c.hold().unwrap_err(),
        "hold",
        "a generic result where status was expected",
    );
}

/// A result that comes after its call timed out does not answer the next call: the timed-out
/// call closed its connection, and the next call gets its own result on a new one.
#[test]
fn a_late_result_after_a_timeout_does_not_answer_the_next_call() {
    let l = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = l.local_addr().unwrap().to_string();
    std::thread::spawn(move || {
        let (first, _) = l.accept().unwrap();
        let mut w = first.try_clone().unwrap();
        let mut lines = BufReader::new(first).lines();
        // `status`: answered late, once the client sent its next command on this connection
        // (or closed it).
        let _status = lines.next();
        let next = lines.next();
        let _ = w.write_all(
            format!(
                "{}
",
                status("PVT", 1.0)
            )
            .as_bytes(),
        );
        if let Some(Ok(_hold)) = next {
            let _ = w.write_all(
                format!(
                    "{}
",
                    status("HOLD", 2.0)
                )
                .as_bytes(),
            );
            return;
        }
        let (second, _) = l.accept().unwrap();
        let mut w = second.try_clone().unwrap();
        if let Some(Ok(_hold)) = BufReader::new(second).lines().next() {
            let _ = w.write_all(
                format!(
                    "{}
",
                    status("HOLD", 2.0)
                )
                .as_bytes(),
            );
        }
    });
    let opts = TcpOptions {
        reply_timeout: Duration::from_millis(100),
        reconnect_on_next_call: true,
        ..TcpOptions::default()
    };
    let mut c = TcpClient::connect_with(&addr, opts).unwrap();
    let e = c.status().unwrap_err();
    assert!(
        matches!(&e, Error::Timeout { command, .. } if command == "status"),
        "{e}"
    );
    c.opts.reply_timeout = Duration::from_secs(10);
    let held = c.hold().unwrap();
    assert_eq!((held.mode, held.time()), (Mode::Hold, 2.0), "{held:?}");
}

#[test]
fn a_velocity_session_sends_its_arguments_and_its_ticks_become_events() {
    let (addr, seen) = server(vec![
        // velocity_control: a tick of an earlier session could not come first; its status.
        vec![status("VELOCITY_CONTROL", 2.0)],
        // set_velocities: refused later, between two ticks.
        vec![
            status("VELOCITY_CONTROL", 2.1),
            refusal_line(
                r#"{"command":"set_velocities","arguments":{"velocities":[0,0,0,900,0,0]}}"#,
            ),
        ],
        // status: answered by a tick (a state as fresh).
        vec![status("VELOCITY_CONTROL", 2.2)],
        // hold: one more tick, then hold's own status.
        vec![status("VELOCITY_CONTROL", 2.3), status("HOLD", 2.4)],
    ]);
    let mut c = TcpClient::connect(&addr).unwrap();
    let o = VelocityOptions {
        timeout_s: Some(0.5),
        dt_status_s: Some(0.01),
    };
    assert_eq!(c.velocity_control(o).unwrap().mode, Mode::VelocityControl);
    c.set_velocities([0.0, 0.0, 0.0, 900.0, 0.0, 0.0]).unwrap();
    assert_eq!(c.status().unwrap().time(), 2.1);
    let held = c.hold().unwrap();
    assert_eq!((held.mode, held.time()), (Mode::Hold, 2.4));
    let mut events = Vec::new();
    while let Some(e) = c.next_event(Duration::from_millis(50)).unwrap() {
        events.push(e);
    }
    assert_eq!(events.len(), 3, "{events:#?}");
    let Event::CommandError(e) = &events[0] else {
        panic!("{events:#?}")
    };
    assert_eq!(
        (e.command.as_str(), e.kind),
        ("set_velocities", ErrorKind::Invalid)
    );
    assert!(matches!(&events[1], Event::Status(s) if s.time() == 2.2));
    assert!(matches!(&events[2], Event::Status(s) if s.time() == 2.3));
    let sent: Vec<Value> = seen
        .try_iter()
        .map(|l| serde_json::from_str(&l).unwrap())
        .collect();
    assert_eq!(sent.len(), 4);
    assert_eq!(sent[0]["command"], "velocity_control");
    assert_eq!(
        sent[0]["arguments"],
        json!({"timeout": 0.5, "dt_status": 0.01})
    );
    assert_eq!(
        sent[1],
        json!({"command": "set_velocities", "arguments": {"velocities": [0.0, 0.0, 0.0, 900.0, 0.0, 0.0]}})
    );
}

#[test]
fn velocity_control_without_timeout_or_ticks_sends_the_protocol_words_for_none() {
    let (addr, seen) = server(vec![vec![status("VELOCITY_CONTROL", 1.0)]]);
    let mut c = TcpClient::connect(&addr).unwrap();
    let o = VelocityOptions {
        timeout_s: None,
        dt_status_s: None,
    };
    c.velocity_control(o).unwrap();
    assert_eq!(c.ticks, None);
    let v: Value = serde_json::from_str(&seen.recv().unwrap()).unwrap();
    assert_eq!(v["arguments"], json!({"timeout": -1.0, "dt_status": 0.0}));
    assert_eq!(VelocityOptions::default().timeout_s, Some(1.0));
}

#[test]
fn wait_until_returns_the_first_state_that_holds_or_names_what_did_not() {
    let (addr, _seen) = server(vec![
        vec![status("PVT", 1.0)],
        vec![status("PVT", 2.0)],
        vec![status("HOLD", 3.0)],
        vec![status("PVT", 4.0)],
    ]);
    let mut c = TcpClient::connect(&addr).unwrap();
    let s = c
        .wait_until("HOLD", Duration::from_secs(5), |s| s.mode == Mode::Hold)
        .unwrap();
    assert_eq!(s.time(), 3.0, "the first state in HOLD");
    let e = c
        .wait_until("at t = 9 s", Duration::ZERO, |s| s.time() == 9.0)
        .unwrap_err();
    assert!(
        matches!(&e, Error::NotReached { last, .. } if last.time() == 4.0),
        "{e}"
    );
    assert!(
        e.to_string()
            .starts_with("at t = 9 s: not reached within 0ns (last state: mode PVT"),
        "{e}"
    );
}

/// `command` sends any command as the contract writes it and returns its typed result;
/// a command that answers nothing on success returns once written.
#[test]
fn any_command_goes_through_command_with_its_typed_result() {
    use mcm_shared::command::{Axis, MoveAxis, SetVelocities, SimCommand};
    use mcm_shared::protocol::results::Answer;
    let (addr, seen) = server(vec![
        vec![r#"{"result_type":"sim","true_position":[1,2,3,4,5,6],"true_velocity":[0,0,0,0,0,0],"emergency_stop":true}"#.into()],
        vec![],
        vec![r#"{"result_type":"generic","error_status":"OK"}"#.into()],
    ]);
    let mut c = TcpClient::connect(&addr).unwrap();
    let sim = SimCommand {
        block_axis: Axis::new(2),
        ..SimCommand::default()
    };
    let Some(Answer::Sim(truth)) = c.command(sim).unwrap() else {
        panic!("a sim result")
    };
    assert!(truth.emergency_stop && truth.true_position[5] == 6.0);
    let v = SetVelocities {
        velocities_deg_s: [0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
    };
    assert_eq!(c.command(v).unwrap(), None);
    let m = MoveAxis {
        axis: Axis::new(3).unwrap(),
        target_deg: 12.5,
        velocity_factor: 0.5,
    };
    assert_eq!(c.command(m).unwrap(), Some(Answer::ok()));
    let sent: Vec<Value> = seen
        .try_iter()
        .map(|l| serde_json::from_str(&l).unwrap())
        .collect();
    assert_eq!(
        sent,
        [
            json!({"command": "sim", "arguments": {"block_axis": 2}}),
            json!({"command": "set_velocities", "arguments": {"velocities": [0.0, 1.0, 0.0, 0.0, 0.0, 0.0]}}),
            json!({"command": "move_axis", "arguments": {"axis_index": 3, "target_position": 12.5, "velocity_factor": 0.5}}),
        ]
    );
}

/// An axis number that is no axis still goes to the MCM, which refuses it in its own words.
#[test]
fn move_axis_leaves_a_bad_axis_to_the_mcm() {
    let refusal = refusal_line(
        r#"{"command":"move_axis","arguments":{"axis_index":9,"target_position":0,"velocity_factor":0.5}}"#,
    );
    let (addr, seen) = server(vec![vec![refusal]]);
    let mut c = TcpClient::connect(&addr).unwrap();
    let e = c.move_axis(9, 0.0, 0.5).unwrap_err();
    let e = e.mcm().expect("the MCM's refusal");
    assert_eq!(e.kind, ErrorKind::Invalid);
    assert!(e.message.contains("\"axis_index\" = 9"), "{}", e.message);
    let sent: Value = serde_json::from_str(&seen.recv().unwrap()).unwrap();
    assert_eq!(
        sent,
        json!({"command": "move_axis", "arguments": {"axis_index": 9, "target_position": 0.0, "velocity_factor": 0.5}})
    );
}

/// A list of points longer than a line goes as several `pvt_points` commands, each within the
/// MCM's limit of a command, in order, every point once.
#[test]
fn pvt_points_are_cut_into_lines_within_the_limit_of_a_command() {
    use mcm_shared::command::PvtPoint;
    let ok = r#"{"result_type":"generic","error_status":"OK"}"#.to_string();
    let (addr, seen) = server(vec![vec![ok.clone()]; 8]);
    let mut c = TcpClient::connect(&addr).unwrap();
    // Long numbers (exact in binary, so that they read back unchanged): 1000 of these points
    // take about 200 KB.
    let points: Vec<PvtPoint> = (0..1000)
        .map(|k| PvtPoint {
            position_deg: [-100.0 - f64::from(k) / 1024.0; 6],
            velocity_deg_s: [98.757_812_5; 6],
        })
        .collect();
    c.pvt_points(&points).unwrap();
    let sent: Vec<String> = seen.try_iter().collect();
    assert!(sent.len() > 1, "one line of {} bytes", sent[0].len());
    let mut got = Vec::new();
    for line in &sent {
        assert!(
            line.len() <= protocol::MAX_COMMAND_BYTES,
            "{} bytes",
            line.len()
        );
        let cmd = Command::from_json(line, &mcm_shared::config::RobotConfig::prob2_default());
        let Ok(Command::PvtPoints(p)) = cmd else {
            panic!("{cmd:?}")
        };
        got.extend(p.points);
    }
    assert!(
        got == points,
        "{} points read back of {}",
        got.len(),
        points.len()
    );
    // Full lines: the next point would not have fit.
    let one = Command::PvtPoints(protocol::PvtPoints {
        points: vec![points[0]],
    })
    .to_json()
    .to_string()
    .len();
    assert!(
        sent[0].len() + one > protocol::MAX_COMMAND_BYTES,
        "{}",
        sent[0].len()
    );
}

/// The Cartesian calls send the pose as the contract writes it and read their typed results.
#[test]
fn a_pose_is_sent_as_written_and_the_solutions_are_read() {
    let ik = r#"{"result_type":"inverse_kinematics","solutions":[[1,2,3,4,5,6],[6,5,4,3,2,1]]}"#;
    let move_all = r#"{"result_type":"move_all","velocities":[1,2,3,4,5,6],"longest":3,"max_time_to_target":1.5}"#;
    let (addr, seen) = server(vec![vec![ik.into()], vec![move_all.into()]]);
    let mut c = TcpClient::connect(&addr).unwrap();
    let pose = Pose {
        position: [0.4, 0.0, 0.5],
        orientation: [0.0, 1.0, 0.0, 0.0],
    };
    let r = c.inverse_kinematics(pose, Some([0.0; 6])).unwrap();
    assert_eq!(
        r.solutions,
        [
            [1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
            [6.0, 5.0, 4.0, 3.0, 2.0, 1.0]
        ]
    );
    assert_eq!(c.move_to_pose(pose, 0.5).unwrap().longest, 3);
    let sent: Vec<Value> = seen
        .try_iter()
        .map(|l| serde_json::from_str(&l).unwrap())
        .collect();
    assert_eq!(
        sent[0],
        json!({"command": "inverse_kinematics", "arguments": {
            "position": [0.4, 0.0, 0.5], "orientation": [0.0, 1.0, 0.0, 0.0],
            "seed": [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]}})
    );
    assert_eq!(
        sent[1],
        json!({"command": "move_to_pose", "arguments": {
            "position": [0.4, 0.0, 0.5], "orientation": [0.0, 1.0, 0.0, 0.0],
            "velocity_factor": 0.5}})
    );
}
