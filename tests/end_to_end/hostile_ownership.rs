//! Hostile clients against control ownership and access (issue 11, items 1 and 2), end to end
//! with the real processes: another client's motion is refused naming the owner while its
//! `hold` works; a torque session with no timeout whose owner disconnects ends in HOLD with the
//! simulated arm's true velocity at rest; motion from a network outside the allow-list is
//! refused while `hold` still works; with a shared secret, take_control needs `authenticate`.
//! Every wait is bounded; times are read from the robot's state, not from the wall clock.

use crate::common;

use common::{
    Client, Mcm, TempConfig, assert_error, assert_ok, assert_status, config_file, max_abs, six,
};
use serde_json::Value;

const DETAIL: &str = r#"{"command":"status","arguments":{"detail":true}}"#;

/// Start an MCM whose configuration is the P-Rob2's plus `extra` TOML.
fn start_with_config(tag: &str, extra: &str) -> (Mcm, TempConfig) {
    let config = config_file(tag, |base| format!("{base}\n{extra}\n"));
    let mcm = Mcm::start_with(tag, &["--config", config.path()]);
    (mcm, config)
}

fn detail(c: &mut Client) -> Value {
    let s = c.request(DETAIL);
    assert_eq!(s["result_type"], "status", "{s}");
    s
}

/// Type `line` into a new HMI session (as `nc` does: no telnet negotiation) and read until
/// `until` appears; the text read.
fn hmi_line(mcm: &Mcm, line: &str, until: &str) -> String {
    use std::io::{Read, Write};
    let mut s = std::net::TcpStream::connect(mcm.hmi).unwrap();
    s.set_read_timeout(Some(std::time::Duration::from_millis(200)))
        .unwrap();
    s.write_all(format!("{line}\n").as_bytes()).unwrap();
    let deadline = std::time::Instant::now() + common::WAIT;
    let mut text = Vec::new();
    let mut buf = [0u8; 4096];
    while !String::from_utf8_lossy(&text).contains(until) {
        assert!(
            std::time::Instant::now() < deadline,
            "the HMI did not answer {line:?} with {until:?}: {}",
            String::from_utf8_lossy(&text)
        );
        if let Ok(n) = s.read(&mut buf) {
            text.extend_from_slice(&buf[..n]);
        }
    }
    String::from_utf8_lossy(&text).into_owned()
}

fn true_velocity(c: &mut Client) -> [f64; 6] {
    let r = c.request(r#"{"command":"sim"}"#);
    assert_eq!(r["result_type"], "sim", "{r}");
    six(&r["true_velocity"])
}

#[test]
fn another_clients_motion_is_refused_naming_the_owner_and_a_gone_owners_torque_session_stops() {
    let mcm = Mcm::start("own");
    let mut a = mcm.client();
    let mut b = mcm.client();
    a.wait_drives_online();
    let d = detail(&mut b);
    assert_eq!(d["detail"]["control"]["owner"], Value::Null, "{d}");

    // A's first motion command takes control implicitly.
    assert_ok(&a.request(r#"{"command":"calibrate"}"#));
    let d = detail(&mut a);
    assert_eq!(d["detail"]["control"]["this_connection"], true, "{d}");
    let d = detail(&mut b);
    let owner = d["detail"]["control"]["owner"].as_str().unwrap_or_default();
    assert!(owner.starts_with("JSON client 127.0.0.1:"), "{d}");
    assert_eq!(d["detail"]["control"]["this_connection"], false, "{d}");

    // B may neither move nor take control; the refusal names A in words.
    assert_status(
        &a.request(r#"{"command":"pvt","arguments":{"dt":0.01}}"#),
        "PVT",
    );
    let refused =
        b.request(r#"{"command":"move_axis","arguments":{"axis_index":1,"target_position":20}}"#);
    assert_error(&refused, &["move_axis refused", owner, "release_control"]);
    assert_error(&b.request(r#"{"command":"take_control"}"#), &[owner]);
    assert_error(&b.request(r#"{"command":"release_control"}"#), &[owner]);

    // B's hold stops A's move: a stop is never refused for lack of control.
    assert_ok(&a.request(
        r#"{"command":"move_axis","arguments":{"axis_index":1,"target_position":40,"velocity_factor":0.5}}"#,
    ));
    assert_status(&b.request(r#"{"command":"hold"}"#), "HOLD");
    let d = detail(&mut b);
    assert!(
        d["detail"]["access"]["refused"]["not_owner"].as_u64() >= Some(3),
        "{d}"
    );

    // A enters a torque session with no timeout, turns axis 6, and disconnects.
    assert_status(
        &a.request(r#"{"command":"torque_control","arguments":{"timeout":-1}}"#),
        "TORQUE_CONTROL",
    );
    a.send_raw(b"{\"command\":\"set_torques\",\"arguments\":{\"torques\":[0,0,0,0,0,0.5]}}\n");
    let deadline = std::time::Instant::now() + common::WAIT;
    while true_velocity(&mut b)[5] < 5.0 {
        assert!(
            std::time::Instant::now() < deadline,
            "axis 6 did not turn under the owner's torque"
        );
    }
    assert_error(
        &b.request(r#"{"command":"set_torques","arguments":{"torques":[0,0,0,0,0,3]}}"#),
        &["set_torques refused", owner],
    );
    let before = detail(&mut b);
    assert_eq!(before["operating_mode"], "TORQUE_CONTROL", "{before}");
    let t_gone = before["detail"]["cycle"].as_u64().unwrap();
    drop(a);

    let held = b.wait_status("HOLD after the owner left", |s| {
        s["operating_mode"] == "HOLD" || s["operating_mode"] == "ERROR"
    });
    assert_eq!(
        held["operating_mode"], "HOLD",
        "a controlled stop, no trip: {held}"
    );
    assert_eq!(held["detail"]["control"]["owner"], Value::Null, "{held}");
    let mut at_rest = true_velocity(&mut b);
    while max_abs(&at_rest) > 0.5 {
        let s = detail(&mut b);
        let cycles = s["detail"]["cycle"].as_u64().unwrap() - t_gone;
        assert!(
            cycles < 2000,
            "not at rest {cycles} cycles after the owner left: {at_rest:?}"
        );
        at_rest = true_velocity(&mut b);
    }
    // Nobody controls the arm now: B may take it.
    assert_ok(&b.request(r#"{"command":"take_control"}"#));
}

#[test]
fn motion_from_outside_the_allowed_networks_is_refused_and_hold_still_works() {
    let (mcm, _config) = start_with_config(
        "net",
        "[gateway.access]\nmotion_networks = [\"10.0.0.0/8\", \"fd00::/8\"]\n",
    );
    let mut c = mcm.client();
    c.wait_drives_online();
    let refused = c.request(r#"{"command":"calibrate"}"#);
    assert_error(
        &refused,
        &[
            "calibrate refused",
            "127.0.0.1",
            "10.0.0.0/8, fd00::/8",
            "motion_networks",
        ],
    );
    assert_error(&c.request(r#"{"command":"take_control"}"#), &["127.0.0.1"]);
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    let d = detail(&mut c);
    let access = &d["detail"]["access"];
    assert_eq!(access["motion_allowed_here"], false, "{d}");
    assert_eq!(access["refused"]["network"], 2, "{d}");
    assert_eq!(d["detail"]["control"]["owner"], Value::Null, "{d}");
    // The HMI is held to the same rules, and its status view says who controls the arm.
    let t = hmi_line(&mcm, "take_control", "motion_networks");
    assert!(t.contains("not accepted from 127.0.0.1"), "{t}");
    let t = hmi_line(&mcm, "status", "control:");
    assert!(t.contains("nobody controls the arm"), "{t}");
    drop(mcm);
}

#[test]
fn with_a_secret_take_control_needs_authenticate_first() {
    // `printf '%s' 'open sesame' | sha256sum`
    let hash = "41ef4bb0b23661e66301aac36066912dac037827b4ae63a7b1165a5aa93ed4eb";
    let dir = std::env::temp_dir().join(common::unique_instance("secret-file"));
    std::fs::create_dir_all(&dir).unwrap();
    let secret_file = dir.join("secret.sha256");
    std::fs::write(&secret_file, format!("{hash}  -\n")).unwrap();
    let (mcm, _config) = start_with_config(
        "secret",
        &format!(
            "[gateway.access]\nsecret_sha256_file = {:?}\n",
            secret_file.display().to_string()
        ),
    );
    let mut a = mcm.client();
    let mut b = mcm.client();
    a.wait_drives_online();
    assert_error(
        &a.request(r#"{"command":"take_control"}"#),
        &["take_control refused", "shared secret", "authenticate"],
    );
    let wrong = a.request(r#"{"command":"authenticate","arguments":{"secret":"open sesame!"}}"#);
    assert_error(&wrong, &["authenticate refused", "secret is wrong"]);
    assert!(
        !wrong.to_string().contains("sesame"),
        "the secret is never echoed: {wrong}"
    );
    assert_ok(&a.request(r#"{"command":"authenticate","arguments":{"secret":"open sesame"}}"#));
    assert_ok(&a.request(r#"{"command":"take_control"}"#));
    let d = detail(&mut a);
    let access = &d["detail"]["access"];
    assert_eq!(access["secret_required"], true, "{d}");
    assert_eq!(access["authenticated"], true, "{d}");
    assert_eq!(access["refused"]["wrong_secret"], 1, "{d}");
    assert_eq!(access["refused"]["not_authenticated"], 1, "{d}");
    assert_eq!(d["detail"]["control"]["this_connection"], true, "{d}");

    // Authentication is per connection; and a second authenticated client is still not the
    // owner.
    assert_error(&b.request(r#"{"command":"release"}"#), &["shared secret"]);
    assert_ok(&b.request(r#"{"command":"authenticate","arguments":{"secret":"open sesame"}}"#));
    assert_error(
        &b.request(r#"{"command":"take_control"}"#),
        &["controlled by JSON client 127.0.0.1:"],
    );
    assert_status(&b.request(r#"{"command":"hold"}"#), "HOLD");
    drop(mcm);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn control_of_a_killed_gateways_connection_is_released_by_its_successor() {
    let mut mcm = Mcm::start("ghost");
    let mut a = mcm.client();
    a.wait_drives_online();
    assert_ok(&a.request(r#"{"command":"calibrate"}"#));
    assert_status(
        &a.request(r#"{"command":"torque_control","arguments":{"timeout":-1}}"#),
        "TORQUE_CONTROL",
    );
    let gw = mcm.gateway_pid;
    // SAFETY: killing the gateway child of our launcher; its connections cannot say goodbye.
    unsafe { libc::kill(gw, libc::SIGKILL) };
    mcm.wait_ready();
    assert_ne!(mcm.gateway_pid, gw);
    let mut b = Client::connect(mcm.json);
    // Without the new gateway's check, the session would run on with a ghost owner forever.
    let held = b.wait_status("the ghost's torque session ended", |s| {
        s["operating_mode"] != "TORQUE_CONTROL"
    });
    assert_eq!(held["operating_mode"], "HOLD", "{held}");
    assert_eq!(held["detail"]["control"]["owner"], Value::Null, "{held}");
    assert_ok(&b.request(r#"{"command":"take_control"}"#));
    drop(a);
}
