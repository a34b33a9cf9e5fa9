//! The examples of `docs/protocol.md` cannot go stale: every checked example (a fenced block
//! whose info string is `json example`, convention at the top of the document) is sent to the
//! simulated arm, in document order, and each reply is compared with the documented one by
//! shape: the same keys at every depth, the same JSON types, arrays of the same length, equal
//! strings (a `...` in a documented string stands for any text) and booleans, equal numbers
//! (within 0.1 %) except under the keys the block's `vary=` lists (`vary=*`: every number),
//! which need only be numbers. A failure names the example by its line and heading, and shows
//! the reply received.

use crate::common;

use common::{Client, Mcm, assert_ok};
use serde_json::Value;
use std::time::{Duration, Instant};

/// One checked example of the document.
struct Example {
    /// `docs/protocol.md:LINE (heading)`.
    name: String,
    /// The mode the arm is brought to first (`mode=...`), if any.
    mode: Option<String>,
    /// Keys whose numbers may differ (`vary=a,b`; `*`: all).
    vary: Vec<String>,
    /// `wait=rest`: wait until the arm is at rest (a move of the block before has ended).
    wait_rest: bool,
    /// Each request line and the replies documented for it.
    steps: Vec<(String, Vec<String>)>,
}

fn examples(doc: &str) -> Vec<Example> {
    let mut out = Vec::new();
    let mut heading = String::new();
    let mut current: Option<Example> = None;
    for (i, line) in doc.lines().enumerate() {
        if current.is_none() {
            if line.starts_with('#') {
                heading = line.trim_start_matches('#').trim().to_string();
            }
            if let Some(info) = line.trim_start().strip_prefix("```json example") {
                let mode = info
                    .split_whitespace()
                    .find_map(|w| w.strip_prefix("mode="))
                    .map(str::to_string);
                let vary = info
                    .split_whitespace()
                    .find_map(|w| w.strip_prefix("vary="))
                    .map(|v| v.split(',').map(str::to_string).collect())
                    .unwrap_or_default();
                current = Some(Example {
                    name: format!("docs/protocol.md:{} ({heading})", i + 1),
                    mode,
                    vary,
                    wait_rest: info.split_whitespace().any(|w| w == "wait=rest"),
                    steps: Vec::new(),
                });
            }
            continue;
        }
        let ex = current.as_mut().unwrap();
        let text = line.trim_start();
        if text.starts_with("```") {
            out.push(current.take().unwrap());
        } else if let Some(req) = text.strip_prefix("-> ") {
            ex.steps.push((req.to_string(), Vec::new()));
        } else if let Some(rep) = text.strip_prefix("<- ") {
            let name = ex.name.clone();
            ex.steps
                .last_mut()
                .unwrap_or_else(|| panic!("{name}: a reply before any request"))
                .1
                .push(rep.to_string());
        } else if !text.is_empty() {
            panic!(
                "{}: a line that is neither `-> ` nor `<- `: {line}",
                ex.name
            );
        }
    }
    assert!(current.is_none(), "an example block is not closed");
    out
}

/// Whether `got` has the shape of `doc`; `Err` names the first difference and where.
fn same_shape(doc: &Value, got: &Value, at: &str, vary: &[String]) -> Result<(), String> {
    let differ = || Err(format!("at {at}: documented {doc}, got {got}"));
    let key = at
        .rsplit('.')
        .next()
        .unwrap_or_default()
        .split('[')
        .next()
        .unwrap_or_default();
    let varies = vary.iter().any(|v| v == "*" || v == key);
    match (doc, got) {
        (Value::Object(d), Value::Object(g)) => {
            let dk: Vec<_> = d.keys().collect();
            let gk: Vec<_> = g.keys().collect();
            if dk != gk {
                return Err(format!("at {at}: documented keys {dk:?}, got keys {gk:?}"));
            }
            d.iter()
                .try_for_each(|(k, v)| same_shape(v, &g[k], &format!("{at}.{k}"), vary))
        }
        (Value::Array(d), Value::Array(g)) if d.len() == g.len() => d
            .iter()
            .zip(g)
            .enumerate()
            .try_for_each(|(i, (d, g))| same_shape(d, g, &format!("{at}[{i}]"), vary)),
        (Value::Number(d), Value::Number(g)) => {
            let (d, g) = (
                d.as_f64().unwrap_or(f64::NAN),
                g.as_f64().unwrap_or(f64::NAN),
            );
            if varies || (d - g).abs() <= 1e-6 + 1e-3 * d.abs() {
                Ok(())
            } else {
                differ()
            }
        }
        (Value::String(d), Value::String(g)) if text_matches(d, g) => Ok(()),
        (Value::Bool(d), Value::Bool(g)) if d == g => Ok(()),
        (Value::Null, Value::Null) => Ok(()),
        _ => differ(),
    }
}

/// `doc` with every `...` standing for any text.
fn text_matches(doc: &str, got: &str) -> bool {
    let parts: Vec<&str> = doc.split("...").collect();
    if parts.len() == 1 {
        return doc == got;
    }
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if !got.starts_with(first) || !got[first.len()..].ends_with(last) {
        return false;
    }
    let mut rest = &got[first.len()..got.len() - last.len()];
    for p in &parts[1..parts.len() - 1] {
        match rest.find(p) {
            Some(i) => rest = &rest[i + p.len()..],
            None => return false,
        }
    }
    true
}

/// Wait (bounded, on the robot's state) until every axis's velocity is 0.
fn wait_at_rest(c: &mut Client) {
    c.wait_status("the arm at rest", |s| {
        s["axis_states"]["velocity"]
            .as_array()
            .is_some_and(|v| v.iter().all(|x| x.as_f64() == Some(0.0)))
    });
}

fn mode_of(c: &mut Client) -> String {
    let s = c.request(r#"{"command":"status"}"#);
    s["operating_mode"].as_str().unwrap_or_default().to_string()
}

/// Bring the calibrated arm to `mode`, at rest: `hold`, the stop's end, then the mode's command.
fn enter(c: &mut Client, mode: &str) {
    // After an example that pressed the emergency stop, `hold` is refused until the drives
    // report it released: retried, bounded. Spontaneous safety errors are skipped.
    let deadline = Instant::now() + common::WAIT;
    loop {
        c.send_raw(b"{\"command\":\"hold\"}\n");
        let hold = c.recv_matching(|v| v.get("check").is_none());
        if hold["operating_mode"] == "HOLD" {
            break;
        }
        assert!(Instant::now() < deadline, "hold: {hold}");
        std::thread::sleep(Duration::from_millis(20));
    }
    wait_at_rest(c);
    let entry = match mode {
        "HOLD" => return,
        "PVT" => r#"{"command":"pvt","arguments":{"dt":0.01}}"#,
        "RELEASE" => r#"{"command":"release"}"#,
        "TORQUE_CONTROL" => r#"{"command":"torque_control","arguments":{"timeout":-1}}"#,
        other => panic!("mode={other} is not a mode an example can start in"),
    };
    let r = c.request(entry);
    assert_eq!(r["operating_mode"], mode, "{entry}: {r}");
}

#[test]
fn the_examples_of_the_protocol_document_get_the_documented_replies() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/protocol.md"))
        .expect("docs/protocol.md");
    let examples = examples(&doc);
    assert!(examples.len() >= 15, "{} examples found", examples.len());
    let mcm = Mcm::start("examples");
    let mut c = mcm.client();
    c.wait_drives_online();
    assert_ok(&c.request(r#"{"command":"calibrate"}"#));
    let mut failures = Vec::new();
    for ex in &examples {
        if let Some(mode) = &ex.mode {
            enter(&mut c, mode);
        }
        if ex.wait_rest {
            wait_at_rest(&mut c);
        }
        for (req, replies) in &ex.steps {
            c.send_raw(format!("{req}\n").as_bytes());
            for rep in replies {
                let doc: Value = serde_json::from_str(rep).unwrap_or_else(|e| {
                    panic!("{}: documented reply is not JSON ({e}): {rep}", ex.name)
                });
                // Spontaneous safety errors (an example that presses the emergency stop) are
                // not replies, unless the example documents one.
                let spontaneous = doc.get("check").is_some();
                let got = c.recv_matching(|v| spontaneous || v.get("check").is_none());
                if let Err(e) = same_shape(&doc, &got, "reply", &ex.vary) {
                    failures.push(format!("{}: `{req}`: {e}\n  received: {got}", ex.name));
                }
            }
        }
        // What the example left running (a move, a stream) ends before the next one.
        if ex.mode.is_some() && mode_of(&mut c) != "HOLD" {
            enter(&mut c, "HOLD");
        }
    }
    assert!(
        failures.is_empty(),
        "stale examples:\n{}",
        failures.join("\n")
    );
}

#[test]
fn shapes_compare_keys_types_lengths_and_fixed_strings() {
    let doc: Value =
        serde_json::from_str(r#"{"a":1.5,"b":["x"],"c":"move ... refused: ..."}"#).unwrap();
    let ok: Value =
        serde_json::from_str(r#"{"a":7,"b":["x"],"c":"move 1 refused: busy"}"#).unwrap();
    let all = ["*".to_string()];
    assert_eq!(same_shape(&doc, &ok, "r", &all), Ok(()));
    assert!(
        same_shape(&doc, &ok, "r", &[]).is_err(),
        "a number that differs"
    );
    assert_eq!(same_shape(&doc, &ok, "r", &["a".to_string()]), Ok(()));
    for bad in [
        r#"{"a":1.5,"b":["x"]}"#,
        r#"{"a":"1.5","b":["x"],"c":"move 1 refused: busy"}"#,
        r#"{"a":1.5,"b":["x","y"],"c":"move 1 refused: busy"}"#,
        r#"{"a":1.5,"b":["y"],"c":"move 1 refused: busy"}"#,
        r#"{"a":1.5,"b":["x"],"c":"move 1 accepted"}"#,
    ] {
        let got: Value = serde_json::from_str(bad).unwrap();
        assert!(same_shape(&doc, &got, "r", &all).is_err(), "{bad}");
    }
    let parsed = examples(
        "# T\n```json example mode=PVT\n-> {\"command\":\"info\"}\n<- {\"a\":1}\n<- {\"b\":2}\n```\n",
    );
    assert_eq!(parsed.len(), 1);
    assert_eq!(parsed[0].mode.as_deref(), Some("PVT"));
    assert_eq!(parsed[0].steps[0].1.len(), 2);
    assert_eq!(parsed[0].name, "docs/protocol.md:2 (T)");
}
