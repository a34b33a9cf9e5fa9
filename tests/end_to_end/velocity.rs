//! End to end, VELOCITY_CONTROL on the simulated arm (the real launcher, over TCP): the ramp
//! seen in the simulation's ground truth, the timeout's controlled stop reported at once (and
//! TORQUE_CONTROL's fallback likewise), a joint driven into its limit stopping before it, the
//! refusals, `hold`, and the HMI's `jog` over a raw telnet connection.
//!
//! Times are the robot's (`axis_states.time`); every wait is bounded; the short pauses only
//! pace polls or stand for a terminal's key auto-repeat.

use crate::common;

use common::{Client, WAIT, assert_error, assert_ok, assert_status, calibrated, six, time_of};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

const CYCLE: f64 = 0.005;
const STATUS: &str = r#"{"command":"status"}"#;

#[test]
fn two_axes_ramp_within_the_acceleration_limit_and_reach_their_targets() {
    let (_mcm, mut c) = calibrated("vel-ramp");
    let r = c.request(r#"{"command":"velocity_control","arguments":{"timeout":-1}}"#);
    assert_status(&r, "VELOCITY_CONTROL");
    c.send_raw(
        b"{\"command\":\"set_velocities\",\"arguments\":{\"velocities\":[20,0,-30,0,0,0]}}\n",
    );
    // No result on success: the next line is the status asked now. Time and velocity from
    // one state each, over windows of at least 50 ms of robot time.
    let sample = |c: &mut Client| {
        let s = c.request(STATUS);
        (time_of(&s), six(&s["axis_states"]["velocity"]))
    };
    let mut last = sample(&mut c);
    let mut worst: f64 = 0.0;
    let deadline = Instant::now() + WAIT;
    loop {
        std::thread::sleep(Duration::from_millis(20));
        let (t, v) = sample(&mut c);
        if t - last.0 >= 0.05 {
            for i in [0, 2] {
                worst = worst.max(((v[i] - last.1[i]) / (t - last.0)).abs());
            }
            last = (t, v);
        }
        let truth = c.truth().1;
        if (truth[0] - 20.0).abs() < 0.3 && (truth[2] + 30.0).abs() < 0.3 {
            break;
        }
        assert!(Instant::now() < deadline, "targets not reached: {truth:?}");
    }
    // 180 deg/s^2 on axes 1 and 3 (polls are not cycle-exact: some slack).
    assert!(
        worst < 180.0 * 1.25,
        "true acceleration up to {worst:.1} deg/s^2"
    );
    assert!(worst > 20.0, "it did accelerate: {worst}");
    let v = c.truth().1;
    // The others are held in place (the arm's coupling makes them tremble a little).
    assert!(v[1].abs() < 1.0 && v[3].abs() < 1.0, "others still: {v:?}");
    // `hold` ends it with a controlled stop.
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    c.wait_truth("at rest after hold", |_, v| {
        v.iter().all(|x| x.abs() < 0.05)
    });
}

/// The status that reports the fallback to HOLD comes in the cycle of the mode change, not at
/// the next `dt_status` tick (1 s here), in both VELOCITY_CONTROL and TORQUE_CONTROL.
#[test]
fn the_timeout_falls_back_to_hold_and_is_reported_at_once() {
    let (_mcm, mut c) = calibrated("vel-timeout");
    for enter in [
        r#"{"command":"velocity_control","arguments":{"timeout":0.5,"dt_status":1.0}}"#,
        r#"{"command":"torque_control","arguments":{"timeout":0.5,"dt_status":1.0}}"#,
    ] {
        let r = c.request(enter);
        let t0 = time_of(&r);
        let hold = c.recv();
        assert_status(&hold, "HOLD");
        let after = time_of(&hold) - t0;
        // The fallback comes in the cycle after 0.5 s; the connection sends the newest state
        // when it wakes, so a loaded machine may show a state a few cycles later, but never
        // the one of the 1 s status tick.
        assert!(
            (0.5..=0.5 + 10.0 * CYCLE).contains(&after),
            "{enter}: HOLD reported {after:.3} s after the mode change's state"
        );
        c.wait_truth("at rest", |_, v| v.iter().all(|x| x.abs() < 0.05));
    }

    // Moving: the timeout's stop is controlled (no trip), and reported at once.
    let r =
        c.request(r#"{"command":"velocity_control","arguments":{"timeout":0.3,"dt_status":1.0}}"#);
    let t0 = time_of(&r);
    c.send_raw(b"{\"command\":\"set_velocities\",\"arguments\":{\"velocities\":[0,0,0,0,0,40]}}\n");
    let hold = c.recv();
    assert_status(&hold, "HOLD");
    assert!(time_of(&hold) - t0 < 0.6, "{hold}");
    assert!(
        six(&hold["axis_states"]["velocity"])[5] > 5.0,
        "still moving when the mode fell back: {hold}"
    );
    c.wait_truth("stopped", |_, v| v[5].abs() < 0.05);
    assert_status(&c.request(STATUS), "HOLD");
}

#[test]
fn a_velocity_towards_a_joint_limit_stops_before_the_limit_without_a_trip() {
    let (_mcm, mut c) = calibrated("vel-limit");
    assert_status(
        &c.request(r#"{"command":"velocity_control","arguments":{"timeout":-1}}"#),
        "VELOCITY_CONTROL",
    );
    // Axis 5: limit 120 deg, 1 deg margin, 150 deg/s.
    c.send_raw(
        b"{\"command\":\"set_velocities\",\"arguments\":{\"velocities\":[0,0,0,0,150,0]}}\n",
    );
    let (p, _) = c.wait_truth("at rest near the limit", |p, v| {
        p[4] > 100.0 && v[4].abs() < 0.02
    });
    assert!(p[4] < 119.0 && p[4] > 118.0, "stopped at {} deg", p[4]);
    assert_status(&c.request(STATUS), "VELOCITY_CONTROL");
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
}

#[test]
fn refused_outside_hold_for_others_and_out_of_range() {
    let (mcm, mut c) = calibrated("vel-refuse");
    assert_error(
        &c.request(r#"{"command":"set_velocities","arguments":{"velocities":[0,0,0,0,0,0]}}"#),
        &["set_velocities", "HOLD"],
    );
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    assert_error(
        &c.request(r#"{"command":"velocity_control"}"#),
        &["velocity_control", "PVT"],
    );
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    let mut other = mcm.client();
    assert_error(
        &other.request(r#"{"command":"velocity_control"}"#),
        &["velocity_control", "controlled by"],
    );
    assert_status(
        &c.request(r#"{"command":"velocity_control","arguments":{"timeout":-1}}"#),
        "VELOCITY_CONTROL",
    );
    assert_error(
        &c.request(r#"{"command":"set_velocities","arguments":{"velocities":[0,0,0,151,0,0]}}"#),
        &[
            "argument \"velocities[3]\" = 151",
            "from -150 to 150 deg/s (the axis's maximum velocity)",
        ],
    );
    assert_error(
        &other.request(r#"{"command":"set_velocities","arguments":{"velocities":[0,0,0,1,0,0]}}"#),
        &["set_velocities", "controlled by"],
    );
    // `hold` is open to all and ends the mode.
    assert_status(&other.request(r#"{"command":"hold"}"#), "HOLD");
    assert_status(&c.recv(), "HOLD");
}

/// The HMI's `jog` over a raw TCP connection (no telnet negotiation), keys sent as a terminal's
/// auto-repeat sends them.
#[test]
fn jog_moves_an_axis_while_a_key_is_held_and_q_leaves_to_hold() {
    // A key every 30 ms of this test's clock keeps the jog going: timing, so alone.
    let _alone = crate::common::machine::alone();
    let (mcm, mut c) = calibrated("vel-jog");
    assert_ok(&c.request(r#"{"command":"release_control"}"#));
    let stream = TcpStream::connect(mcm.hmi).unwrap();
    let screen = Arc::new(Mutex::new(Vec::<u8>::new()));
    let mut rd = stream.try_clone().unwrap();
    let sink = screen.clone();
    std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n) = rd.read(&mut buf) {
            if n == 0 {
                break;
            }
            sink.lock().unwrap().extend_from_slice(&buf[..n]);
        }
    });
    let text = |s: &Arc<Mutex<Vec<u8>>>| String::from_utf8_lossy(&s.lock().unwrap()).to_string();
    let wait_text = |what: &str| {
        let deadline = Instant::now() + WAIT;
        while !text(&screen).contains(what) {
            assert!(Instant::now() < deadline, "no {what:?}: {}", text(&screen));
            std::thread::sleep(Duration::from_millis(10));
        }
    };
    let mut w = stream;
    wait_text("quit` to leave.");
    w.write_all(b"jog 2 20\r\n").unwrap();
    wait_text("jog axis 2");
    assert_status(&c.request(STATUS), "VELOCITY_CONTROL");
    // `+` held down: a repeat every 30 ms for 1.5 s.
    let start = c.truth().0[1];
    let mut peak: f64 = 0.0;
    for _ in 0..50 {
        w.write_all(b"+").unwrap();
        std::thread::sleep(Duration::from_millis(30));
        peak = peak.max(c.truth().1[1]);
    }
    assert!(
        (19.0..=20.5).contains(&peak),
        "jog speed 20 deg/s: peak {peak}"
    );
    // Let go: the axis stops, the mode stays.
    c.wait_truth("stopped after the key", |_, v| v[1].abs() < 0.05);
    let moved = c.truth().0[1] - start;
    assert!(moved > 15.0, "moved {moved} deg");
    assert_status(&c.request(STATUS), "VELOCITY_CONTROL");
    // The arrow key the other way.
    for _ in 0..20 {
        w.write_all(b"\x1b[D").unwrap();
        std::thread::sleep(Duration::from_millis(30));
    }
    assert!(c.truth().1[1] < -5.0);
    w.write_all(b"q").unwrap();
    wait_text("jog ended; mode HOLD");
    assert_status(&c.request(STATUS), "HOLD");
    c.wait_truth("at rest", |_, v| v[1].abs() < 0.05);
    let shown = text(&screen);
    assert!(
        shown.contains("position") && shown.contains("deg/s"),
        "{shown}"
    );
}
