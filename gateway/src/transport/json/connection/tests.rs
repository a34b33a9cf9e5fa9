//! The JSON channel against hostile input: a real connection to [`crate::transport::json::run`]
//! with a bridge whose real-time core is not running, and property tests of the framing and
//! parsing path ([`Decoder`] -> [`step`]) over arbitrary bytes, arbitrary JSON values and
//! mutated valid commands.

use super::*;
use crate::test_support::offline_context;
use mcm_shared::protocol::json::to_ascii;
use proptest::prelude::*;
use std::time::Duration;
use tokio::io::{AsyncBufReadExt, BufReader};
use tokio::net::TcpListener;

const WAIT: Duration = Duration::from_secs(10);

/// The line that used to panic the connection task (an excerpt cut inside `é`).
fn panicking_line() -> String {
    format!(
        "{{\"command\":\"calibrate\",\"arguments\":{{\"which\":\"{}\\u00e9\"}}}}\n",
        "a".repeat(58)
    )
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_hostile_line_gets_an_ascii_error_and_the_connection_lives_on() {
    let (ctx, thread, _) = offline_context("conn", RobotConfig::prob2_default());
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(crate::transport::json::run(listener, ctx, async move {
        let _ = stopped.await;
    }));

    let socket = TcpStream::connect(addr).await.unwrap();
    let (rd, mut wr) = socket.into_split();
    let mut lines = BufReader::new(rd).lines();
    let mut next = async || {
        tokio::time::timeout(WAIT, lines.next_line())
            .await
            .expect("a reply in time")
            .unwrap()
            .expect("the connection is still open")
    };
    let input = format!(
        "{}{}{}{}",
        panicking_line(),
        // The same in the HMI's form: a raw `é` (refused by the framing as non-ASCII).
        panicking_line().replace("\\u00e9", "\u{e9}"),
        "{\"command\":\"nope\",\"command\":\"status\"}\n",
        "{\"command\":\"status\"}\n"
    );
    wr.write_all(input.as_bytes()).await.unwrap();

    let first = next().await;
    assert!(first.is_ascii(), "{first}");
    let v: Value = serde_json::from_str(&first).unwrap();
    assert_eq!(v["error_status"], "ERROR", "{first}");
    assert!(
        first.contains("\\u00e9..."),
        "escaped and cut after 60 characters: {first}"
    );
    let second = next().await;
    assert!(second.contains("non-ASCII byte 0xC3"), "{second}");
    let third = next().await;
    assert!(third.contains(r#"duplicate key \"command\""#), "{third}");
    let fourth: Value = serde_json::from_str(&next().await).unwrap();
    assert_eq!(fourth["result_type"], "generic");
    assert!(
        fourth["error_message"]
            .as_str()
            .unwrap()
            .contains("not running"),
        "{fourth}"
    );

    let _ = stop.send(());
    tokio::time::timeout(WAIT, server).await.unwrap().unwrap();
    thread.stop();
}

#[test]
fn duplicate_arguments_are_refused_by_name() {
    let cfg = RobotConfig::prob2_default();
    let line = r#"{"command":"move_axis","arguments":{"axis_index":9,"axis_index":6,"target_position":0}}"#;
    let Step::Reply(v) = step(Frame::Object(line.into()), &cfg) else {
        panic!("a duplicate argument must not run")
    };
    let msg = v["error_message"].as_str().unwrap();
    assert!(msg.contains("duplicate key \"axis_index\""), "{msg}");
}

#[test]
fn the_oversize_reply_names_the_limit() {
    let cfg = RobotConfig::prob2_default();
    let Step::Close(v) = step(Frame::Oversize, &cfg) else {
        panic!("oversize closes")
    };
    assert!(v["error_message"].as_str().unwrap().contains("65536 bytes"));
    assert_eq!(v["error_code"], "line_too_long", "{v}");
    let Step::Reply(v) = step(
        Frame::Invalid {
            reason: "not JSON".into(),
        },
        &cfg,
    ) else {
        panic!("a line that is no object is answered")
    };
    assert_eq!(v["error_code"], "invalid_json", "{v}");
}

/// A line refused before it became a command is `invalid`, and names the command it names
/// (a refusal of `set_velocities`, sent without waiting, is known by it); a line that names
/// no known command names none.
#[test]
fn a_refused_line_is_invalid_and_names_the_command_it_names() {
    let cfg = RobotConfig::prob2_default();
    let ended = |step: Step| match step {
        Step::Reply(v) | Step::Close(v) => (v["outcome"].clone(), v.get("command").cloned()),
        Step::Run(cmd) => panic!("{cmd:?} runs"),
        Step::Foreign(kind) => panic!("{kind:?} closes without a word"),
    };
    let line = r#"{"command":"set_velocities","arguments":{"velocities":[1]}}"#;
    assert_eq!(
        ended(step(Frame::Object(line.into()), &cfg)),
        ("invalid".into(), Some("set_velocities".into()))
    );
    let unnamed = [
        Frame::Object(r#"{"command":"stauts"}"#.into()),
        Frame::Object(r#"{"arguments":{}}"#.into()),
        Frame::Invalid {
            reason: "not JSON".into(),
        },
        Frame::Oversize,
    ];
    for frame in unnamed {
        assert_eq!(ended(step(frame, &cfg)), ("invalid".into(), None));
    }
}

/// Feed `input` in reads of `chunk` bytes; each frame must give one ASCII result (an ERROR,
/// or a command to execute). Returns the steps.
fn run_path(input: &[u8], chunk: usize) -> Vec<Step> {
    let cfg = RobotConfig::prob2_default();
    let mut d = Decoder::new();
    let mut steps = Vec::new();
    for part in input.chunks(chunk.max(1)) {
        d.extend(part);
        while let Some(f) = d.next_frame() {
            let s = step(f, &cfg);
            if let Step::Reply(v) | Step::Close(v) = &s {
                let line = to_ascii(v);
                assert!(line.is_ascii(), "{line}");
                let back: Value = serde_json::from_str(&line).unwrap();
                assert!(back["result_type"].is_string(), "{line}");
                assert!(back["error_message"].is_string(), "{line}");
            }
            let close = matches!(s, Step::Close(_));
            steps.push(s);
            if close {
                return steps;
            }
        }
    }
    steps
}

/// Every complete non-blank line gives at least one step; exactly one when it does not start
/// with `{` or is one whole ASCII JSON object (a line such as `{"a":1}x` is an object and the
/// rest of its line: two). The lines are checked alone and all together.
fn one_step_per_line(lines: &[Vec<u8>]) {
    let mut input = Vec::new();
    let mut at_least = 0;
    for l in lines {
        let mut line = l.clone();
        line.push(b'\n');
        input.extend_from_slice(&line);
        let text = String::from_utf8_lossy(l);
        let t = text.trim_matches([' ', '\t', '\r']);
        if t.is_empty() {
            continue;
        }
        at_least += 1;
        let steps = run_path(&line, 5).len();
        let one_object =
            t.is_ascii() && t.starts_with('{') && serde_json::from_str::<Value>(t).is_ok();
        if !t.starts_with('{') || one_object {
            assert_eq!(steps, 1, "{text:?}");
        } else {
            assert!(steps >= 1, "{text:?}");
        }
    }
    let steps = run_path(&input, 7);
    assert!(steps.len() >= at_least, "{} < {at_least}", steps.len());
}

const VALID: &[&str] = &[
    r#"{"command":"status","arguments":{"detail":true}}"#,
    r#"{"command":"move_axis","arguments":{"axis_index":1,"target_position":30,"velocity_factor":0.5}}"#,
    r#"{"command":"move_all","arguments":{"target_positions":[0,10,20,0,0,0]}}"#,
    r#"{"command":"calibrate","arguments":{"which":"WRIST"}}"#,
    r#"{"command":"set_torques","arguments":{"torques":[0,0,0,0,0,0]}}"#,
    r#"{"command":"pvt_points","arguments":{"points":[{"t":0.1,"p":[0,0,0,0,0,0],"v":[0,0,0,0,0,0]}]}}"#,
    r#"{"command":"sim","arguments":{"fault":1}}"#,
    r#"{"command":"torque_control","arguments":{"dt_status":0.1}}"#,
];

/// A valid command with a few random byte edits (replace, insert, delete).
fn mutated() -> impl Strategy<Value = Vec<u8>> {
    (
        prop::sample::select(VALID),
        prop::collection::vec((any::<prop::sample::Index>(), any::<u8>(), 0u8..3), 0..6),
    )
        .prop_map(|(line, edits)| {
            let mut b = line.as_bytes().to_vec();
            for (at, byte, kind) in edits {
                let i = at.index(b.len() + 1);
                match kind {
                    0 if i < b.len() => b[i] = byte,
                    1 => b.insert(i, byte),
                    _ if i < b.len() => {
                        b.remove(i);
                    }
                    _ => {}
                }
            }
            b.retain(|&c| c != b'\n');
            b
        })
}

/// Arbitrary JSON values (also fed to the HMI's parser by its property tests).
pub(crate) fn json_value() -> impl Strategy<Value = Value> {
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::from),
        any::<i64>().prop_map(Value::from),
        any::<f64>()
            .prop_filter("finite", |x| x.is_finite())
            .prop_map(Value::from),
        ".{0,70}".prop_map(Value::from),
    ];
    leaf.prop_recursive(4, 32, 6, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(Value::from),
            prop::collection::btree_map(
                prop_oneof![
                    Just("command".to_string()),
                    Just("arguments".to_string()),
                    ".{0,8}"
                ],
                inner,
                0..6
            )
            .prop_map(|m| Value::Object(m.into_iter().collect())),
        ]
    })
}

proptest! {
    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..2048), chunk in 1usize..64) {
        run_path(&bytes, chunk);
    }

    #[test]
    fn arbitrary_lines_get_a_result_each(
        lines in prop::collection::vec(prop::collection::vec(any::<u8>().prop_filter("no newline", |b| *b != b'\n'), 0..200), 0..12)
    ) {
        one_step_per_line(&lines);
    }

    #[test]
    fn mutated_commands_get_a_result_each(lines in prop::collection::vec(mutated(), 1..8)) {
        one_step_per_line(&lines);
    }

    #[test]
    fn arbitrary_json_values_get_one_result(v in json_value(), command in prop::sample::select(mcm_shared::protocol::command_names().collect::<Vec<_>>())) {
        for value in [v.clone(), serde_json::json!({"command": command, "arguments": v})] {
            let line = to_ascii(&value);
            let steps = run_path(format!("{line}\n").as_bytes(), 4096);
            prop_assert_eq!(steps.len(), 1, "{}", line);
        }
    }
}

#[test]
fn a_torque_session_sends_one_status_per_due_cycle_on_the_robots_clock() {
    use super::ModeSession as TorqueSession;
    const P: u64 = 5_000_000;
    let start = StateSample {
        t_ns: 1_000_000_000,
        mode: Mode::TorqueControl.to_wire(),
        ..StateSample::default()
    };
    // dt_status = one period: every cycle is due, whatever its wake-up jitter.
    let mut s = TorqueSession::new(0.005, Some(&start));
    let jitter = [30_000, 2_000, 900_000, 0, 45_000, 1_000];
    for (k, j) in jitter.iter().enumerate() {
        let t = start.t_ns + (k as u64 + 1) * P + j;
        assert!(s.due(t, P), "cycle {k} is due");
        assert!(
            !s.due(t, P),
            "cycle {k}: the same state is never sent twice"
        );
    }
    // dt_status = two periods: every other cycle.
    let mut s = TorqueSession::new(0.010, Some(&start));
    let sent: Vec<bool> = (1..=6)
        .map(|k| s.due(start.t_ns + k * P + 20_000, P))
        .collect();
    assert_eq!(sent, [false, true, false, true, false, true]);
    // Far behind (the connection was slow): no burst, the next one period later.
    let mut s = TorqueSession::new(0.005, Some(&start));
    let late = start.t_ns + 100 * P;
    assert!(s.due(late, P));
    assert!(!s.due(late + P / 4, P));
    assert!(s.due(late + P, P));
    // No statuses asked (dt_status 0): never due, only the final one is sent.
    let mut s = TorqueSession::new(0.0, Some(&start));
    assert!(!s.due(start.t_ns + P, P));
}

/// Item of issue 14: the state that leaves the session's mode is reported in the cycle it is
/// published, not at the next `dt_status` tick; states of the mode wait for their tick.
#[test]
fn a_mode_session_reports_leaving_its_mode_at_once() {
    use super::{ModeSession, SessionStep};
    const P: u64 = 5_000_000;
    for mode in [Mode::TorqueControl, Mode::VelocityControl] {
        let start = StateSample {
            t_ns: 1_000_000_000,
            mode: mode.to_wire(),
            ..StateSample::default()
        };
        let mut s = ModeSession::new(1.0, Some(&start));
        let at = |k: u64, m: Mode| {
            let mut st = start;
            st.t_ns = start.t_ns + k * P;
            st.timing.period_ns = P;
            st.mode = m.to_wire();
            st
        };
        for k in 1..101 {
            assert_eq!(
                s.on_state(&at(k, mode)),
                SessionStep::Quiet,
                "{mode}: cycle {k}"
            );
        }
        // The timeout's fallback in cycle 101 (0.505 s), long before the 1 s tick.
        assert_eq!(
            s.on_state(&at(101, Mode::Hold)),
            SessionStep::Left,
            "{mode}"
        );
        // A due tick in the mode is a status.
        let mut s = ModeSession::new(1.0, Some(&start));
        assert_eq!(s.on_state(&at(200, mode)), SessionStep::Status);
        assert_eq!(s.on_state(&at(201, Mode::Error)), SessionStep::Left);
    }
}

#[test]
fn lost_events_are_told_with_their_code() {
    let v = events_lost(3);
    assert_eq!(v["error_code"], "events_lost", "{v}");
    assert_eq!(
        v["error_message"],
        "3 safety errors were not delivered to this slow connection"
    );
}
