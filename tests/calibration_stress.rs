//! End to end: calibration that cannot lie. Every group and direction the manual allows is
//! calibrated while busy-loop processes load every CPU, and each result must be within
//! 0.05 deg of the simulation's truth; an aborted re-calibration keeps the previous
//! calibration; an obstacle in the way of a re-calibration fails it with both positions.
//!
//! `MCM_CALIB_STRESS_REPS=n` repeats the list of calibrations n times (default 1: about a
//! minute and a half on 2 cores).

mod common;

use common::{Client, Mcm, assert_error, assert_ok, max_diff, six};
use serde_json::{Value, json};
use std::process::{Child, Command, Stdio};

/// Busy-loop child processes, one per CPU; killed (each by its own pid) on drop.
struct Load(Vec<Child>);

impl Load {
    fn every_cpu() -> Load {
        let n = std::thread::available_parallelism().map_or(2, |n| n.get());
        Load(
            (0..n)
                .map(|_| {
                    Command::new("sh")
                        .args(["-c", "while :; do :; done"])
                        .stdin(Stdio::null())
                        .spawn()
                        .expect("start a busy loop")
                })
                .collect(),
        )
    }
}

impl Drop for Load {
    fn drop(&mut self) {
        for c in &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

/// Wait (bounded) until the true arm is at rest; then the reported positions must be the true
/// angles within 0.05 deg, and every axis calibrated.
fn assert_positions_true(c: &mut Client, what: &str) {
    c.wait_truth(&format!("{what}: the arm at rest"), |_, v| {
        v.iter().all(|x| x.abs() < 0.01)
    });
    let s = c.request(r#"{"command":"status","arguments":{"detail":true}}"#);
    let (t, _) = c.truth();
    let p = six(&s["axis_states"]["position"]);
    let err = max_diff(&p, &t);
    assert!(
        err < 0.05,
        "{what}: reported {p:?} vs true {t:?} (off by {err:.3} deg)"
    );
    assert_eq!(
        s["detail"]["all_calibrated"], true,
        "{what}: every axis calibrated: {s}"
    );
}

/// Every `calibrate` the manual allows: ALL in both wrist and elbow directions and with the
/// mechanical stops forced, each group, and single axes with a stop and with a light barrier.
const RUNS: &[&str] = &[
    r#"{"which":"ALL"}"#,
    r#"{"which":"ALL","wrist_direction":-1}"#,
    r#"{"which":"ALL","elbow_direction":-1,"wrist_direction":-1}"#,
    r#"{"which":"ALL","force_mechanical_stop":true}"#,
    r#"{"which":"ELBOW"}"#,
    r#"{"which":"ELBOW","elbow_direction":-1}"#,
    r#"{"which":"WRIST","wrist_direction":-1}"#,
    r#"{"which":"WRIST"}"#,
    r#"{"which":2}"#,
    r#"{"which":5,"wrist_direction":-1}"#,
    r#"{"which":1}"#,
];

#[test]
fn every_calibration_is_true_while_other_processes_load_every_cpu() {
    let reps: usize = common::env_or("MCM_CALIB_STRESS_REPS", 1);
    let mcm = Mcm::start("calib-stress");
    let mut c = mcm.client();
    c.wait_drives_online();
    let _load = Load::every_cpu();
    for rep in 0..reps {
        for args in RUNS {
            let what = format!("repetition {rep}, calibrate {args}");
            let r = c.request(&format!(r#"{{"command":"calibrate","arguments":{args}}}"#));
            assert_ok(&r);
            assert_positions_true(&mut c, &what);
        }
    }
}

/// Calibrated, the arm somewhere gravity matters.
fn calibrated(c: &mut Client) {
    c.wait_drives_online();
    assert_ok(&c.request(r#"{"command":"calibrate"}"#));
    assert_positions_true(c, "first calibration");
}

#[test]
fn an_aborted_recalibration_keeps_the_previous_calibration() {
    let mcm = Mcm::start("calib-abort");
    let mut c = mcm.client();
    calibrated(&mut c);
    for args in [r#"{"which":3}"#, r#"{"which":"ELBOW"}"#] {
        c.send_raw(format!("{{\"command\":\"calibrate\",\"arguments\":{args}}}\n").as_bytes());
        // Let it search a while (bounded wait on the robot's own state), then hold.
        let mut other = mcm.client();
        let start = other.wait_status("calibrating", |s| s["operating_mode"] == "CALIBRATION");
        let cycle0 = start["detail"]["cycle"].as_u64().unwrap();
        other.wait_status("searching for 1.5 s", |s| {
            s["detail"]["cycle"].as_u64().unwrap() > cycle0 + 300
        });
        let hold = other.request(r#"{"command":"hold"}"#);
        assert_eq!(hold["operating_mode"], "HOLD", "{hold}");
        assert_error(&c.recv(), &["calibrate failed", "aborted"]);
        assert_positions_true(&mut c, &format!("after the aborted calibrate {args}"));
    }
}

#[test]
fn an_obstacle_in_the_way_of_a_recalibration_fails_it_with_both_positions() {
    let mcm = Mcm::start("calib-obstacle");
    let mut c = mcm.client();
    calibrated(&mut c);
    let r = c.request(r#"{"command":"pvt","arguments":{"dt":0.01}}"#);
    assert_eq!(r["operating_mode"], "PVT", "{r}");
    assert_ok(&c.request(
        r#"{"command":"move_axis","arguments":{"axis_index":3,"target_position":100,"velocity_factor":0.5}}"#,
    ));
    c.wait_truth("axis 3 at 100 deg", |p, _| (p[2] - 100.0).abs() <= 0.01);
    assert_eq!(c.request(r#"{"command":"hold"}"#)["operating_mode"], "HOLD");
    let r = c.request(r#"{"command":"sim","arguments":{"block_axis":3}}"#);
    assert_eq!(r["result_type"], "sim", "{r}");
    // The command's ERROR and the spontaneous safety error the failure also is arrive in
    // either order: the gateway delivers spontaneous errors as they come, between a command's
    // lines, and both come from the same cycle here.
    c.send_raw(b"{\"command\":\"calibrate\",\"arguments\":{\"which\":3}}\n");
    let (mut reply, mut spontaneous) = (None, None);
    while reply.is_none() || spontaneous.is_none() {
        let v = c.recv();
        if v.get("check").is_some() {
            spontaneous = Some(v);
        } else {
            reply = Some(v);
        }
    }
    let r: Value = reply.expect("the calibrate's result");
    let e = spontaneous.expect("the spontaneous safety error");
    assert_eq!(
        (&e["check"], &e["axis"]),
        (&json!("calibration_failed"), &json!(3)),
        "{e}"
    );
    assert_error(
        &r,
        &[
            "calibration of axis 3 failed",
            "by its previous calibration",
            "configured at 140.000 deg",
            "axis 3 is no longer calibrated",
        ],
    );
    // It ran, then failed: its `outcome` says so, not its words.
    assert_eq!(
        (r["command"].as_str(), r["outcome"].as_str()),
        (Some("calibrate"), Some("failed")),
        "{r}"
    );
    let msg = r["error_message"].as_str().unwrap();
    let found: f64 = msg
        .split("found at ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no found position in {msg:?}"));
    assert!((found - 100.0).abs() < 1.0, "found at {found}: {msg}");
    c.send_raw(b"{\"command\":\"sim\",\"arguments\":{\"unblock_axis\":3}}\n");
    c.recv_matching(|v| v["result_type"] == "sim");
    c.send_raw(b"{\"command\":\"hold\"}\n");
    let r = c.recv_matching(|v| v["result_type"] == "status");
    assert_eq!(r["operating_mode"], "HOLD", "{r}");
    // One of the two calibrations was wrong: axis 3's previous one is dropped, and the next
    // calibration, the obstacle gone, finds the true angle.
    let s = c.request(r#"{"command":"status","arguments":{"detail":true}}"#);
    let calibrated: Vec<bool> = serde_json::from_value(s["detail"]["calibrated"].clone())
        .unwrap_or_else(|e| panic!("no calibrated flags ({e}): {s}"));
    assert_eq!(calibrated, [true, true, false, true, true, true], "{s}");
    assert_ok(&c.request(r#"{"command":"calibrate","arguments":{"which":3}}"#));
    assert_positions_true(&mut c, "calibrated again after the implausible reference");
}
