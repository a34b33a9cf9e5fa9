//! End to end: the walking skeleton. Starts the real launcher (mcm-rt + mcm-gateway) and speaks
//! the JSON protocol over TCP.

use crate::common;

use common::{Client, Mcm, alive, assert_error};
use serde_json::Value;

fn six(v: &Value) -> usize {
    v.as_array().map_or(0, Vec::len)
}

#[test]
fn status_at_start_is_off_with_six_axes() {
    let mcm = Mcm::start("status");
    let mut c = mcm.client();
    let s = c.request(r#"{"command":"status"}"#);
    assert_eq!(s["result_type"], "status", "{s}");
    assert_eq!(s["operating_mode"], "OFF", "{s}");
    for field in ["time", "position", "velocity", "acceleration", "current"] {
        assert_eq!(six(&s["axis_states"][field]), 6, "{field} in {s}");
    }
}

#[test]
fn hold_powers_the_drives_and_info_describes_the_robot() {
    let mcm = Mcm::start("hold");
    let mut c = mcm.client();
    c.wait_drives_online();
    let s = c.request(r#"{"command":"hold"}"#);
    assert_eq!(s["result_type"], "status", "{s}");
    assert_eq!(s["operating_mode"], "HOLD", "{s}");
    let d = c.request(r#"{"command":"status","arguments":{"detail":true}}"#);
    assert!(
        d["detail"]["drive_enabled"]
            .as_array()
            .unwrap()
            .iter()
            .all(|x| x == true),
        "{d}"
    );

    let i = c.request(r#"{"command":"info"}"#);
    assert_eq!(i["result_type"], "initialization", "{i}");
    assert_eq!(i["num_axes"], 6, "{i}");
    assert_eq!(i["cycle_time"], 0.005, "{i}");
    assert_eq!(six(&i["axes"]), 6, "{i}");
}

#[test]
fn garbage_gets_errors_and_the_connection_keeps_working() {
    let mcm = Mcm::start("garbage");
    let mut c = mcm.client();
    assert_error(&c.request("hello"), &["invalid JSON"]);
    assert_error(&c.request("[1,2,3]"), &["JSON array"]);
    assert_error(
        &c.request(r#"{"command":"fly"}"#),
        &["unknown command \"fly\""],
    );
    assert_error(
        &c.request(r#"{"command":"stauts"}"#),
        &["did you mean \"status\""],
    );
    assert_error(
        &c.request(r#"{"command":"move_axis","arguments":{"axis_index":9,"target_position":0}}"#),
        &["axis_index", "9", "1 to 6"],
    );
    c.send_raw("{\"command\":\"st\u{e4}tus\"}\n".as_bytes());
    assert_error(&c.recv(), &["non-ASCII"]);
    assert_error(&c.request(r#"{"command":"release"}"#), &["release refused"]);
    let s = c.request(r#"{"command":"status"}"#);
    assert_eq!(s["result_type"], "status", "still working: {s}");
}

#[test]
fn oversize_command_gets_one_error_then_the_connection_closes() {
    let mcm = Mcm::start("oversize");
    let mut c = mcm.client();
    let mut big = b"{\"command\":\"".to_vec();
    big.extend(std::iter::repeat_n(b'a', 70 * 1024));
    c.send_raw(&big);
    assert_error(&c.recv(), &["longer than the limit of 65536 bytes"]);
    assert!(
        c.closed(),
        "the connection must be closed after an oversize command"
    );
    // Other clients are unaffected.
    let s = mcm.client().request(r#"{"command":"status"}"#);
    assert_eq!(s["result_type"], "status");
}

#[test]
fn the_manuals_python_example_without_newline_gets_its_reply() {
    let mcm = Mcm::start("python");
    let mut c = mcm.client();
    c.send_raw(br#"{"command":"status"}"#);
    let r = c.recv();
    assert_eq!(r["result_type"], "status", "{r}");
    // Two objects back to back in one write, CRLF, whitespace between them.
    c.send_raw(b"{\"command\":\"info\"}  \r\n{\"command\":\"status\"}");
    assert_eq!(c.recv()["result_type"], "initialization");
    assert_eq!(c.recv()["result_type"], "status");
}

#[test]
fn two_instances_run_side_by_side_without_interfering() {
    let a = Mcm::start("side-a");
    let b = Mcm::start("side-b");
    assert_ne!(a.json, b.json);
    let mut ca = a.client();
    let mut cb = b.client();
    ca.wait_drives_online();
    assert_eq!(
        ca.request(r#"{"command":"hold"}"#)["operating_mode"],
        "HOLD"
    );
    assert_eq!(
        cb.request(r#"{"command":"status"}"#)["operating_mode"],
        "OFF"
    );
    assert_eq!(
        ca.request(r#"{"command":"status"}"#)["operating_mode"],
        "HOLD"
    );
}

#[test]
fn killing_the_gateway_leaves_the_core_running_and_a_new_gateway_reconnects() {
    let mut mcm = Mcm::start("killgw");
    let mut c = mcm.client();
    c.wait_drives_online();
    assert_eq!(c.request(r#"{"command":"hold"}"#)["operating_mode"], "HOLD");
    let before =
        c.request(r#"{"command":"status","arguments":{"detail":true}}"#)["detail"]["cycle"]
            .as_u64()
            .unwrap();
    let (rt, gw) = (mcm.rt_pid, mcm.gateway_pid);
    // SAFETY: killing the gateway child of our launcher.
    unsafe { libc::kill(gw, libc::SIGKILL) };
    // The launcher restarts the gateway; the core keeps running through it.
    mcm.wait_ready();
    assert_ne!(mcm.gateway_pid, gw);
    assert_eq!(mcm.rt_pid, rt);
    assert!(alive(rt), "mcm-rt must survive the gateway");
    let mut c = Client::connect(mcm.json);
    let s = c.request(r#"{"command":"status","arguments":{"detail":true}}"#);
    assert_eq!(
        s["operating_mode"], "HOLD",
        "the same core, still holding: {s}"
    );
    assert!(s["detail"]["cycle"].as_u64().unwrap() > before, "{s}");
}

#[test]
fn sigterm_stops_both_processes_and_a_restart_works() {
    let mcm = Mcm::start("restart");
    let instance = mcm.instance.clone();
    let (rt, gw) = (mcm.rt_pid, mcm.gateway_pid);
    let status = mcm.stop();
    assert!(status.success(), "launcher exit status {status}");
    assert!(!alive(rt) && !alive(gw), "both children stopped");
    // Same instance name again right away: no stale shared memory in the way.
    let again = Mcm::start_named(&instance, &[]);
    assert_eq!(
        again.client().request(r#"{"command":"status"}"#)["operating_mode"],
        "OFF"
    );
}
