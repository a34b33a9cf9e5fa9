use super::*;
use std::io::{BufRead, BufReader, Write};

/// A loop that answers every request with the truth of a pressed switch, or refuses torques.
fn fake_arm(rx: Receiver<Request>) {
    std::thread::spawn(move || {
        for r in rx {
            let answer = match r.command.external_torques_nm {
                Some(t) if t.iter().any(|v| !v.is_finite()) => {
                    Err(SimCommandError::TorqueNotFinite {
                        index: 0,
                        value: t[0],
                    })
                }
                _ => Ok(SimTruth {
                    position: [0.5; 6],
                    velocity: [0.0; 6],
                    emergency_stop: r.command.emergency_stop.unwrap_or(false),
                }),
            };
            let _ = r.answer.send(answer);
        }
    });
}

fn ask(text: &str) -> serde_json::Value {
    let (tx, rx) = channel();
    fake_arm(rx);
    answer(text, &tx, &RobotConfig::prob2_default()).to_value()
}

#[test]
fn a_sim_command_is_answered_with_the_truth_in_degrees() {
    let v = ask(r#"{"command":"sim","arguments":{"emergency_stop":true}}"#);
    assert_eq!(v["result_type"], "sim", "{v}");
    assert_eq!(v["emergency_stop"], true, "{v}");
    let deg = v["true_position"][0].as_f64().unwrap();
    assert!((deg - 28.647_89).abs() < 1e-3, "{v}");
}

#[test]
fn other_commands_and_bad_lines_get_errors_that_say_why() {
    let v = ask(r#"{"command":"hold"}"#);
    let words = v["error_message"].as_str().unwrap();
    assert!(
        words.contains("only `sim`") && words.contains("`hold`"),
        "{v}"
    );
    let v = ask(r#"{"command":"sim","arguments":{"block_axis":9}}"#);
    assert_eq!(v["error_status"], "ERROR", "{v}");
    assert!(
        v["error_message"].as_str().unwrap().contains("block_axis"),
        "{v}"
    );
    let v = ask("not json");
    assert_eq!(v["error_status"], "ERROR", "{v}");
}

#[test]
fn a_stopped_arm_is_said_so() {
    let (tx, rx) = channel::<Request>();
    drop(rx);
    let v = answer(r#"{"command":"sim"}"#, &tx, &RobotConfig::prob2_default()).to_value();
    assert!(
        v["error_message"].as_str().unwrap().contains("stopping"),
        "{v}"
    );
}

#[test]
fn the_socket_serves_lines_and_closes_an_overlong_one() {
    let (addr, rx) = serve("127.0.0.1:0".parse().unwrap(), RobotConfig::prob2_default()).unwrap();
    fake_arm(rx);
    let stream = TcpStream::connect(addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .unwrap();
    let mut out = stream.try_clone().unwrap();
    let mut lines = BufReader::new(stream);
    let mut line = String::new();
    writeln!(out, "\n{{\"command\":\"sim\"}}").unwrap();
    lines.read_line(&mut line).unwrap();
    assert!(line.contains(r#""result_type":"sim""#), "{line}");
    out.write_all(&vec![b'x'; MAX_LINE + 10]).unwrap();
    line.clear();
    lines.read_line(&mut line).unwrap();
    assert!(line.contains("longer than"), "{line}");
    line.clear();
    assert_eq!(lines.read_line(&mut line).unwrap(), 0, "closed: {line}");
}
