//! End to end, one test per command and operating mode: the real launcher (mcm-rt +
//! mcm-gateway) over TCP, with every claim about the arm checked against the simulation's
//! ground truth (`sim`: `true_position`, `true_velocity`), not only against what the MCM says
//! about itself.
//!
//! Times are the robot's (`axis_states.time` of status results) where the robot is measured;
//! `std::time::Instant` only bounds waits, and times the gateway's own `sleep` from below.
//! Every wait is bounded; there are no fixed sleeps used as synchronisation (the short pauses
//! in polling loops only pace the polls).

use crate::common;

use common::{
    Client, Mcm, WAIT, assert_error, assert_ok, assert_status, calibrated, max_abs, max_diff,
    move_all, move_axis, six, time_of,
};
use mcm_shared::config::RobotConfig;
use serde_json::{Value, json};
use std::f64::consts::PI;
use std::time::{Duration, Instant};

const STATUS_DETAIL: &str = r#"{"command":"status","arguments":{"detail":true}}"#;
/// One control cycle of the P-Rob2 [s].
const CYCLE: f64 = 0.005;
/// How late a poll over TCP may see an event that already happened [s].
const POLL_SLACK: f64 = 0.03;
/// The longest a command taken by the gateway may take to reach the core and be served, on the
/// robot's clock [s]: the next cycle, or a few more when the machine is loaded.
const TO_CORE: f64 = 10.0 * CYCLE;
/// How old the newest state may be when the gateway answers `status` with it [s]: a cycle, or
/// a few when the machine is loaded and the core publishes late.
const STATE_AGE: f64 = 10.0 * CYCLE;
/// Pause between polls (pacing only; every loop ends on an observed condition).
const POLL_PAUSE: Duration = Duration::from_millis(5);

// ---------------------------------------------------------------------------------------------
// Helpers

fn position(s: &Value) -> [f64; 6] {
    six(&s["axis_states"]["position"])
}

fn velocity(s: &Value) -> [f64; 6] {
    six(&s["axis_states"]["velocity"])
}

fn current(s: &Value) -> [f64; 6] {
    six(&s["axis_states"]["current"])
}

fn detail6(s: &Value, field: &str) -> [f64; 6] {
    six(&s["detail"][field])
}

/// The ground truth of the simulated arm.
struct Truth {
    position: [f64; 6],
    velocity: [f64; 6],
}

fn sim(c: &mut Client, args: Option<Value>) -> Truth {
    let cmd = match args {
        Some(a) => json!({"command": "sim", "arguments": a}).to_string(),
        None => r#"{"command":"sim"}"#.to_string(),
    };
    let r = c.request(&cmd);
    assert_eq!(r["result_type"], "sim", "{r}");
    Truth {
        position: six(&r["true_position"]),
        velocity: six(&r["true_velocity"]),
    }
}

fn truth(c: &mut Client) -> Truth {
    sim(c, None)
}

fn status(c: &mut Client) -> Value {
    let s = c.request(r#"{"command":"status"}"#);
    assert_eq!(s["result_type"], "status", "{s}");
    s
}

fn detail(c: &mut Client) -> Value {
    let s = c.request(STATUS_DETAIL);
    assert_eq!(s["result_type"], "status", "{s}");
    s
}

/// Poll for `seconds` of robot time, calling `each` between polls with the latest status.
fn observe(c: &mut Client, seconds: f64, mut each: impl FnMut(&mut Client, &Value)) {
    let t0 = time_of(&status(c));
    let deadline = Instant::now() + WAIT;
    loop {
        let s = status(c);
        each(c, &s);
        if time_of(&s) >= t0 + seconds {
            return;
        }
        assert!(Instant::now() < deadline, "robot time stands still: {s}");
        std::thread::sleep(POLL_PAUSE);
    }
}

/// Poll status and truth until `done(status, truth)`; panics after [`WAIT`].
fn wait_until(
    c: &mut Client,
    what: &str,
    mut done: impl FnMut(&Value, &Truth) -> bool,
) -> (Value, Truth) {
    let deadline = Instant::now() + WAIT;
    loop {
        let s = detail(c);
        let t = truth(c);
        if done(&s, &t) {
            return (s, t);
        }
        assert!(
            Instant::now() < deadline,
            "timed out waiting for {what}; last status {s}; true position {:?}",
            t.position
        );
        std::thread::sleep(POLL_PAUSE);
    }
}

/// Wait until the true arm is at rest (every true velocity below 0.1 deg/s).
fn wait_at_rest(c: &mut Client) -> Truth {
    wait_until(c, "the arm at rest", |_, t| max_abs(&t.velocity) < 0.1).1
}

/// In PVT: wait until the commanded motion has ended and the true arm is within 0.05 deg of
/// `target`; returns the status that showed it.
fn wait_arrived(c: &mut Client, target: &[f64; 6]) -> (Value, Truth) {
    wait_until(c, "arrival at the target", |s, t| {
        max_abs(&velocity(s)) == 0.0 && max_diff(&t.position, target) < 0.05
    })
}

fn pvt_points(points: &[([f64; 6], [f64; 6])]) -> String {
    let points: Vec<Value> = points
        .iter()
        .map(|(p, v)| json!({"position": p, "velocity": v}))
        .collect();
    json!({"command": "pvt_points", "arguments": {"points": points}}).to_string()
}

/// The sine of the PVT tests, the same on every axis, from rest at 0: `A (1 - cos wt)` with
/// A = 10 deg, w = pi (0.5 Hz), at point `k` of spacing 0.01 s.
fn sine_point(k: usize) -> ([f64; 6], [f64; 6]) {
    let (a, w) = (10.0, PI);
    let t = k as f64 * 0.01;
    let p = a * (1.0 - (w * t).cos());
    let v = a * w * (w * t).sin();
    ([p; 6], [v; 6])
}

/// The P-Rob2 configuration the launcher runs (embedded in the binaries).
fn config() -> RobotConfig {
    RobotConfig::prob2_default()
}

/// Whether a current is on the grid the drives measure in (per-mille of the rated current).
fn on_drive_grid(current_a: f64, rated_a: f64) -> bool {
    let permille = current_a / rated_a * 1000.0;
    (permille - permille.round()).abs() < 1e-3
}

// ---------------------------------------------------------------------------------------------
// 1. calibrate

#[test]
fn calibrate_finds_the_true_angles_returns_to_zero_and_wrist_redoes_only_axes_4_to_6() {
    let mcm = Mcm::start("calibrate");
    let mut c = mcm.client();
    c.wait_drives_online();
    // Before: raw encoder positions, off from the true angles by an unknown offset.
    let before = detail(&mut c);
    assert_status(&before, "OFF");
    assert_eq!(before["detail"]["all_calibrated"], false, "{before}");
    let t = truth(&mut c);
    assert!(
        max_diff(&position(&before), &t.position) > 0.5,
        "uncalibrated positions are raw encoder angles: {:?} vs true {:?}",
        position(&before),
        t.position
    );

    // Straight from OFF: enables the drives, calibrates, returns to zero.
    let r = c.request(r#"{"command":"calibrate"}"#);
    assert_ok(&r);
    let s = detail(&mut c);
    assert_status(&s, "HOLD");
    assert_eq!(
        s["detail"]["calibrated"],
        json!([true, true, true, true, true, true]),
        "{s}"
    );
    assert_eq!(s["detail"]["all_calibrated"], true, "{s}");
    let t = wait_at_rest(&mut c);
    let s = detail(&mut c);
    assert!(
        max_diff(&position(&s), &t.position) < 0.05,
        "reported {:?} vs true {:?}",
        position(&s),
        t.position
    );
    assert!(
        max_abs(&t.position) < 0.1,
        "back at zero: true position {:?}",
        t.position
    );

    // WRIST (from HOLD): axes 4-6 only. Watch the truth while it runs (from a second
    // connection; the first one waits for the reply). The first connection took control with
    // its calibrate: it hands it over.
    assert_ok(&c.request(r#"{"command":"release_control"}"#));
    let mut w = mcm.client();
    w.send_raw(br#"{"command":"calibrate","arguments":{"which":"WRIST"}}"#);
    w.send_raw(b"\n");
    let (s, _) = wait_until(&mut c, "CALIBRATION", |s, _| {
        s["operating_mode"] == "CALIBRATION"
    });
    assert_eq!(
        s["detail"]["calibrated"],
        json!([true, true, true, false, false, false]),
        "only the wrist axes lose their calibration: {s}"
    );
    let start = t.position;
    let mut wrist_travel = [0.0f64; 6];
    loop {
        let s = detail(&mut c);
        let t = truth(&mut c);
        for i in 0..6 {
            wrist_travel[i] = wrist_travel[i].max((t.position[i] - start[i]).abs());
        }
        for i in 0..3 {
            assert!(
                (t.position[i] - start[i]).abs() < 0.05,
                "axis {} must not move in a WRIST calibration: {:?} -> {:?}",
                i + 1,
                start,
                t.position
            );
        }
        if s["operating_mode"] != "CALIBRATION" {
            break;
        }
        std::thread::sleep(POLL_PAUSE);
    }
    assert_ok(&w.recv());
    // Axes 4 and 6 find the edge of their light barrier at 0 deg (a back-off and a slow
    // approach from there); axis 5 drives to its mechanical stop at -125 deg.
    for (i, travel) in wrist_travel.iter().enumerate().skip(3) {
        let least = if i == 4 { 100.0 } else { 1.0 };
        assert!(
            *travel > least,
            "axis {} searched its reference: travelled {travel} deg",
            i + 1
        );
    }
    let s = detail(&mut c);
    assert_status(&s, "HOLD");
    assert_eq!(s["detail"]["all_calibrated"], true, "{s}");
    let t = wait_at_rest(&mut c);
    let s = detail(&mut c);
    assert!(
        max_diff(&position(&s), &t.position) < 0.05,
        "reported {:?} vs true {:?}",
        position(&s),
        t.position
    );
    assert!(max_abs(&t.position) < 0.1, "back at zero: {:?}", t.position);
}

// ---------------------------------------------------------------------------------------------
// 2. move_all, move_axis

#[test]
fn move_all_arrives_together_on_time_and_on_target() {
    let cfg = config();
    let (_mcm, mut c) = calibrated("move-all");
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    wait_at_rest(&mut c);

    let target = [10.0, -10.0, 40.0, 20.0, -15.0, 25.0];
    let factor = 0.8;
    let before = detail(&mut c);
    // In PVT the status position is the commanded one, where the planned move starts.
    let start = position(&before);
    let t0 = time_of(&before);
    let overruns0 = before["detail"]["timing"]["overruns"].as_u64().unwrap();
    let r = c.request(&move_all(&target, factor));
    assert_eq!(r["result_type"], "move_all", "{r}");
    let v = six(&r["velocities"]);
    let longest = r["longest"].as_u64().expect("longest") as usize;
    let duration = r["max_time_to_target"]
        .as_f64()
        .expect("max_time_to_target");

    // A straight line in joint space: peak velocities in proportion to the distances, none
    // above its share of the axis maximum, and axis 3 (40 deg at 72 deg/s) takes longest.
    let dist: [f64; 6] = std::array::from_fn(|i| (target[i] - start[i]).abs());
    for i in 0..6 {
        let vmax = factor * cfg.axes[i].max_velocity_deg_s;
        assert!(v[i] >= 0.0 && v[i] <= vmax + 1e-6, "axis {}: {r}", i + 1);
        let ratio = v[i] / dist[i];
        let ratio3 = v[2] / dist[2];
        assert!(
            (ratio - ratio3).abs() < 0.01 * ratio3,
            "velocities in proportion to the distances {dist:?}: {r}"
        );
    }
    assert_eq!(longest, 3, "{r}");
    // At least distance / peak velocity, at most that plus the time to reach the peak.
    let cruise = dist[2] / v[2];
    assert!(
        duration >= cruise && duration <= cruise + 2.0 * v[2] / 180.0 + 0.05,
        "max_time_to_target {duration} for {} deg at {} deg/s: {r}",
        dist[2],
        v[2]
    );

    // Arrival: the first status with every velocity 0 and the truth within 0.05 deg.
    let mut was_moving = false;
    let (arrived, t) = wait_until(&mut c, "arrival", |s, t| {
        max_abs(&velocity(s)) == 0.0 && max_diff(&t.position, &target) < 0.05
    });
    let took = time_of(&arrived) - t0;
    let overruns = arrived["detail"]["timing"]["overruns"].as_u64().unwrap() - overruns0;
    let slack = 0.05 * duration + CYCLE + POLL_SLACK;
    eprintln!("move_all: arrived after {took:.3} s, max_time_to_target {duration:.3} s");
    assert!(
        (took - duration).abs() <= slack,
        "arrived after {took:.3} s, max_time_to_target {duration:.3} s (+-{slack:.3} s); \
         {overruns} cycle overruns meanwhile"
    );
    assert!(
        max_diff(&t.position, &target) < 0.05,
        "true {:?} vs target {target:?}",
        t.position
    );
    assert!(max_diff(&position(&arrived), &target) < 1e-6, "{arrived}");
    // It stays there.
    observe(&mut c, 0.3, |c, s| {
        let t = truth(c);
        assert!(
            max_diff(&t.position, &target) < 0.05,
            "stays on target: {:?}",
            t.position
        );
        was_moving |= max_abs(&velocity(s)) > 0.0;
    });
    assert!(!was_moving, "no motion after arrival");
}

#[test]
fn move_axis_moves_only_its_axis_and_hold_stops() {
    let (_mcm, mut c) = calibrated("move-axis");
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    let start = wait_at_rest(&mut c).position;

    // (Moves sent while this one runs re-plan: tests/end_to_end/replan.rs.)
    assert_ok(&c.request(&move_axis(2, 15.0, 0.5)));

    let mut target = start;
    target[1] = 15.0;
    let mut moved_others: f64 = 0.0;
    let (s, t) = wait_until(&mut c, "axis 2 at 15 deg", |s, t| {
        moved_others = (0..6)
            .filter(|i| *i != 1)
            .map(|i| (t.position[i] - start[i]).abs())
            .fold(moved_others, f64::max);
        max_abs(&velocity(s)) == 0.0 && (t.position[1] - 15.0).abs() < 0.05
    });
    assert!(
        moved_others < 0.05,
        "only axis 2 moves: the others moved up to {moved_others} deg"
    );
    assert!(max_diff(&t.position, &target) < 0.05, "{:?}", t.position);
    assert_status(&s, "PVT");

    // A longer move of axis 1, stopped by `hold` part way.
    assert_ok(&c.request(&move_axis(1, 40.0, 0.5)));
    let (_, t) = wait_until(&mut c, "axis 1 moving", |_, t| t.position[0] > 5.0);
    let at_hold = t.position[0];
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    let rest = wait_at_rest(&mut c).position;
    assert!(
        rest[0] > at_hold && rest[0] < 30.0,
        "stopped part way (hold at {at_hold:.2} deg, rest at {:.2} deg of 40)",
        rest[0]
    );
    observe(&mut c, 0.5, |c, s| {
        assert_eq!(s["operating_mode"], "HOLD", "{s}");
        let t = truth(c);
        assert!(
            max_diff(&t.position, &rest) < 0.05,
            "holds where it stopped: {rest:?} -> {:?}",
            t.position
        );
    });
}

// ---------------------------------------------------------------------------------------------
// 3. pvt_points

#[test]
fn pvt_points_stream_a_sine_that_the_true_arm_tracks() {
    let (_mcm, mut c) = calibrated("pvt-stream");
    assert_status(
        &c.request(r#"{"command":"pvt","arguments":{"dt":0.01}}"#),
        "PVT",
    );
    let rest = wait_at_rest(&mut c).position;
    assert!(max_abs(&rest) < 0.1, "{rest:?}");

    // Bad batches at rest: refused whole, nothing queued, nothing moves.
    let mut bad: Vec<_> = (1..=10).map(sine_point).collect();
    bad[9].0[2] = 200.0; // beyond the axis limits
    assert_error(
        &c.request(&pvt_points(&bad)),
        &[
            "pvt_points",
            "point 10: axis 3 position 200 deg exceeds the limit",
        ],
    );
    let mut bad: Vec<_> = (1..=10).map(sine_point).collect();
    bad[5].0[3] += 5.0; // within the limits, but a jump no axis can follow
    assert_error(
        &c.request(&pvt_points(&bad)),
        &[
            "pvt_points refused",
            "point 6",
            "axis 4",
            "nothing was queued",
        ],
    );
    let s = detail(&mut c);
    assert_eq!(s["detail"]["pvt_queue"]["queued"], 0, "{s}");
    assert_status(&s, "PVT");
    assert!(max_diff(&truth(&mut c).position, &rest) < 0.01);

    // The stream: 3 s (one and a half periods), ending at rest at 20 deg.
    let n = 300;
    let batch = 25;
    let points: Vec<_> = (1..=n).map(sine_point).collect();
    let mut sent = 0;
    let send_batch = |c: &mut Client, sent: &mut usize| {
        let end = (*sent + batch).min(n);
        assert_ok(&c.request(&pvt_points(&points[*sent..end])));
        *sent = end;
    };
    send_batch(&mut c, &mut sent);
    send_batch(&mut c, &mut sent);

    let mut worst_following: f64 = 0.0;
    let mut worst_tracking: f64 = 0.0;
    let mut peak: f64 = 0.0;
    let mut bad_batch_sent = false;
    let deadline = Instant::now() + WAIT;
    loop {
        // Bracket the truth between two statuses: it must lie on the commanded path between
        // them (within the tracking band).
        let s1 = detail(&mut c);
        let t = truth(&mut c);
        let s2 = detail(&mut c);
        for s in [&s1, &s2] {
            assert_status(s, "PVT");
            assert_eq!(s["detail"]["pvt_queue"]["starved"], false, "{s}");
            worst_following = worst_following.max(max_abs(&detail6(s, "following_error")));
        }
        let (c1, c2) = (
            detail6(&s1, "commanded_position"),
            detail6(&s2, "commanded_position"),
        );
        for i in 0..6 {
            let lo = c1[i].min(c2[i]);
            let hi = c1[i].max(c2[i]);
            let off = (lo - t.position[i]).max(t.position[i] - hi).max(0.0);
            worst_tracking = worst_tracking.max(off);
        }
        peak = peak.max(t.position.iter().copied().fold(f64::MIN, f64::max));
        let queued = s2["detail"]["pvt_queue"]["queued"].as_u64().unwrap();
        if sent < n && queued < 30 {
            if !bad_batch_sent && sent >= 100 {
                // A bad batch mid-stream: refused whole; the queue does not grow.
                let mut bad = points[sent..sent + batch].to_vec();
                bad[10].0[0] += 5.0;
                assert_error(
                    &c.request(&pvt_points(&bad)),
                    &[
                        "pvt_points refused",
                        "point 11",
                        "axis 1",
                        "nothing was queued",
                    ],
                );
                let after = detail(&mut c);
                let q = after["detail"]["pvt_queue"]["queued"].as_u64().unwrap();
                assert!(q <= queued, "nothing queued: {queued} -> {q}");
                bad_batch_sent = true;
            }
            send_batch(&mut c, &mut sent);
        }
        if sent == n && queued == 0 && max_abs(&velocity(&s2)) == 0.0 {
            break;
        }
        assert!(Instant::now() < deadline, "stream did not end: {s2}");
    }
    assert!(bad_batch_sent);
    eprintln!(
        "pvt stream: following error up to {worst_following:.4} deg, truth off the \
         commanded path up to {worst_tracking:.4} deg, peak {peak:.3} deg"
    );
    assert!(
        worst_following < 0.1,
        "following error up to {worst_following} deg"
    );
    assert!(
        worst_tracking < 0.1,
        "true position up to {worst_tracking} deg off the commanded path"
    );
    assert!(
        peak > 19.0,
        "the arm went through the sine: peak {peak} deg"
    );
    let last = points[n - 1].0;
    let t = wait_at_rest(&mut c);
    assert!(
        max_diff(&t.position, &last) < 0.05,
        "ends on the last point {last:?}: {:?}",
        t.position
    );
    let s = detail(&mut c);
    assert_status(&s, "PVT");
    assert_eq!(s["detail"]["pvt_queue"]["starved"], false, "{s}");
}

#[test]
fn pvt_points_underrun_stops_the_axes_and_says_starved_without_error() {
    let (_mcm, mut c) = calibrated("pvt-underrun");
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    wait_at_rest(&mut c);
    // Half a second of the sine, then nothing: the stream runs dry at full speed.
    let points: Vec<_> = (1..=50).map(sine_point).collect();
    assert_ok(&c.request(&pvt_points(&points)));
    let last = points[49].0[0];
    let (s, _) = wait_until(&mut c, "starved", |s, _| {
        s["detail"]["pvt_queue"]["starved"] == true
    });
    assert_status(&s, "PVT");
    let t = wait_at_rest(&mut c);
    // Stopped beyond the last point (it was moving at 31 deg/s), within its braking distance.
    for p in t.position {
        assert!(
            p > last && p < last + 5.0,
            "stopped after the last point {last:.2}: {:?}",
            t.position
        );
    }
    let s = detail(&mut c);
    assert_status(&s, "PVT");
    assert_eq!(s["detail"]["pvt_queue"]["starved"], true, "{s}");
    assert_eq!(s["detail"]["pvt_queue"]["queued"], 0, "{s}");
    // The drives' loops pull the last hundredths of a degree in (the gravity feed-forward
    // changes with the pose at a bounded rate): settled, the arm then holds.
    let (_, t) = wait_until(&mut c, "the arm settled", |_, t| {
        max_abs(&t.velocity) < 0.02
    });
    observe(&mut c, 0.3, |c, s| {
        assert_status(s, "PVT");
        let now = truth(c).position;
        assert!(
            max_diff(&now, &t.position) < 0.05,
            "holds: settled at {:?}, now {now:?}",
            t.position
        );
    });
    // Still usable: a move is accepted.
    assert_ok(&c.request(&move_axis(1, 0.0, 1.0)));
}

// ---------------------------------------------------------------------------------------------
// 4. release

#[test]
fn release_floats_follows_a_push_and_stays_where_left() {
    let (_mcm, mut c) = calibrated("release");
    // A pose where gravity matters, then RELEASE.
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    let pose = [0.0, 30.0, 30.0, 0.0, 20.0, 0.0];
    move_to(&mut c, &pose);
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    assert_status(&c.request(r#"{"command":"release"}"#), "RELEASE");

    // No hand: it floats (gravity compensated) without drifting.
    let a = truth(&mut c).position;
    let t0 = time_of(&status(&mut c));
    let mut fastest: f64 = 0.0;
    observe(&mut c, 2.0, |c, s| {
        assert_status(s, "RELEASE");
        fastest = fastest.max(max_abs(&truth(c).velocity));
    });
    let b = truth(&mut c).position;
    let dt = time_of(&status(&mut c)) - t0;
    let drift = max_diff(&a, &b) / dt;
    eprintln!("release: drift {drift:.4} deg/s, fastest {fastest:.3} deg/s over {dt:.3} s");
    // (Entering RELEASE the arm settles by a few hundredths of a degree at up to a few deg/s
    // while the drives hand over from position control to torque; it must not fall.)
    assert!(
        drift < 0.5 && fastest < 5.0,
        "drift {drift:.3} deg/s (fastest {fastest:.3} deg/s) over {dt:.2} s: {a:?} -> {b:?}"
    );

    // A hand pushes axis 1 with 5 Nm for 0.3 s, then lets go.
    sim(
        &mut c,
        Some(json!({"external_torques": [5, 0, 0, 0, 0, 0]})),
    );
    observe(&mut c, 0.3, |_, _| {});
    sim(
        &mut c,
        Some(json!({"external_torques": [0, 0, 0, 0, 0, 0]})),
    );
    let rest = wait_at_rest(&mut c).position;
    assert!(
        rest[0] - b[0] > 1.0,
        "the push moved axis 1: {b:?} -> {rest:?}"
    );
    // Afterwards it stays where it was left.
    observe(&mut c, 1.0, |c, s| {
        assert_status(s, "RELEASE");
        let t = truth(c).position;
        assert!(
            max_diff(&t, &rest) < 0.5,
            "stays where left: {rest:?} -> {t:?}"
        );
    });
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
}

/// In PVT: move_all to `target` at full speed and wait until the true arm is there.
fn move_to(c: &mut Client, target: &[f64; 6]) {
    let r = c.request(&move_all(target, 1.0));
    assert_eq!(r["result_type"], "move_all", "{r}");
    wait_arrived(c, target);
}

// ---------------------------------------------------------------------------------------------
// 5. torque_control, set_torques

#[test]
fn torque_control_sends_status_every_dt_status_and_falls_back_to_hold_on_timeout() {
    let (mcm, mut c) = calibrated("torque");
    let a = wait_at_rest(&mut c).position;
    let r =
        c.request(r#"{"command":"torque_control","arguments":{"timeout":0.2,"dt_status":0.05}}"#);
    assert_status(&r, "TORQUE_CONTROL");

    // The manual's loop: wait for a status result, answer with set_torques at once; for 0.5 s
    // of the robot's clock (the status results' `time`). Each read is bounded by WAIT.
    let mut times: Vec<f64> = Vec::new();
    while times.last().is_none_or(|t| t - times[0] < 0.5) {
        let s = c.recv();
        assert_status(&s, "TORQUE_CONTROL");
        times.push(time_of(&s));
        c.send_raw(format!("{ZERO_TORQUES}\n").as_bytes());
    }
    let n = times.len();
    let gaps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    let mean = (times[n - 1] - times[0]) / (n - 1) as f64;
    assert!(
        (0.045..=0.06).contains(&mean) && gaps.iter().all(|g| *g > 0.02 && *g < 0.1),
        "status intervals {gaps:?}"
    );
    assert!(
        (9..=12).contains(&n),
        "{n} status results in 0.5 s of robot time at dt_status 0.05 s: {times:?}"
    );
    // When the gateway took that last set_torques: a detailed status sent right behind it on
    // this connection is answered from the newest state once the gateway has read both.
    c.send_raw(format!("{STATUS_DETAIL}\n").as_bytes());
    let taken = c.recv_matching(|s| {
        assert_status(s, "TORQUE_CONTROL");
        s.get("detail").is_some()
    });
    let (last_status, taken) = (times[n - 1], time_of(&taken));
    // Another connection is not in the session: plain request/reply.
    let mut other = mcm.client();
    assert_status(&status(&mut other), "TORQUE_CONTROL");
    let b = truth(&mut other).position;
    assert!(
        max_diff(&a, &b) < 0.1,
        "zero torques hold the arm still: {a:?} -> {b:?}"
    );

    // No more set_torques: 0.2 s (robot time) after the core took the last one the mode falls
    // back to HOLD, and this connection is told at once with the status of that cycle. The
    // core took it after the state it answered (`last_status`) and, give or take the
    // gateway's way to the core, when the gateway had read it (`taken`).
    let hold = c.recv_matching(|s| {
        assert_eq!(s["result_type"], "status", "{s}");
        s["operating_mode"] != "TORQUE_CONTROL"
    });
    assert_status(&hold, "HOLD");
    let left = time_of(&hold);
    eprintln!(
        "torque_control: {n} status results, intervals {gaps:?}; HOLD {:.3} s after the last \
         status answered, {:.3} s after the gateway took the answer",
        left - last_status,
        left - taken
    );
    assert!(
        left - last_status >= 0.2 && left - taken <= 0.2 + TO_CORE,
        "HOLD at {left:.3} s: the last set_torques answered the state of {last_status:.3} s and \
         was taken by the gateway at {taken:.3} s (timeout 0.2 s, way to the core at most \
         {TO_CORE} s)"
    );
    assert_status(&status(&mut c), "HOLD");
    let t = wait_at_rest(&mut other).position;
    assert!(max_diff(&a, &t) < 0.1, "still: {a:?} -> {t:?}");
}

// ---------------------------------------------------------------------------------------------
// 6. sleep

#[test]
fn sleep_delays_only_its_own_connection() {
    let mcm = Mcm::start("sleep");
    let mut a = mcm.client();
    let mut b = mcm.client();
    assert_status(&status(&mut a), "OFF");
    assert_error(
        &a.request(r#"{"command":"sleep","arguments":{"duration":-1}}"#),
        &["sleep", "duration", "-1"],
    );
    assert_error(&a.request(r#"{"command":"sleep"}"#), &["sleep", "duration"]);

    // On the robot's clock: A's sleep starts after the state of `before`.
    let before = time_of(&status(&mut a));
    let t0 = Instant::now();
    a.send_raw(
        b"{\"command\":\"sleep\",\"arguments\":{\"duration\":1}}\n{\"command\":\"status\"}\n",
    );
    let sb = status(&mut b);
    assert_ok(&a.recv());
    // The sleep is the gateway's, on its clock: the OK cannot come earlier than 1 s.
    let slept = t0.elapsed();
    assert!(slept >= Duration::from_secs(1), "slept {slept:?}");
    let sa = a.recv();
    assert_status(&sa, "OFF");
    let (b_at, a_at) = (time_of(&sb) - before, time_of(&sa) - before);
    eprintln!(
        "sleep: robot time from before the sleep to B's status {b_at:.3} s, to A's {a_at:.3} s"
    );
    // A's next command ran after the sleep; B's status was answered before A's sleep could
    // have ended.
    assert!(
        a_at >= 1.0 - STATE_AGE,
        "A's status shows the state {a_at:.3} s after the one before its sleep of 1 s"
    );
    assert!(
        b_at < 1.0 - STATE_AGE,
        "another connection is answered at once, not after the sleep: B's status shows the \
         state {b_at:.3} s after the one before A's sleep"
    );
}

// ---------------------------------------------------------------------------------------------
// 7. refusals in every wrong mode

const ZERO_MOVE_AXIS: &str =
    r#"{"command":"move_axis","arguments":{"axis_index":1,"target_position":0}}"#;
const ZERO_MOVE_ALL: &str =
    r#"{"command":"move_all","arguments":{"target_positions":[0,0,0,0,0,0]}}"#;
const ZERO_POINTS: &str = r#"{"command":"pvt_points","arguments":{"points":[{"position":[0,0,0,0,0,0],"velocity":[0,0,0,0,0,0]}]}}"#;
const ZERO_TORQUES: &str = r#"{"command":"set_torques","arguments":{"torques":[0,0,0,0,0,0]}}"#;

/// `(name, request)` of every command that changes something.
fn commands() -> Vec<(&'static str, &'static str)> {
    vec![
        ("calibrate", r#"{"command":"calibrate"}"#),
        ("release", r#"{"command":"release"}"#),
        ("pvt", r#"{"command":"pvt"}"#),
        (
            "torque_control",
            r#"{"command":"torque_control","arguments":{"timeout":-1}}"#,
        ),
        ("set_torques", ZERO_TORQUES),
        ("move_axis", ZERO_MOVE_AXIS),
        ("move_all", ZERO_MOVE_ALL),
        ("pvt_points", ZERO_POINTS),
    ]
}

/// Send every command of `names`; each must be refused naming the mode `mode`.
fn refused_in(c: &mut Client, mode: &str, names: &[&str]) {
    for (name, req) in commands() {
        if !names.contains(&name) {
            continue;
        }
        let r = c.request(req);
        assert_error(
            &r,
            &[
                &format!("{name} refused"),
                &format!("not allowed in mode {mode}"),
            ],
        );
    }
    assert_status(&status(c), mode);
}

#[test]
fn every_command_is_refused_in_every_wrong_mode_naming_the_mode() {
    let mcm = Mcm::start("refusals");
    let mut c = mcm.client();
    c.wait_drives_online();
    let moving = ["move_axis", "move_all", "pvt_points", "set_torques"];
    let entries = ["release", "pvt", "torque_control"];

    // OFF: everything but calibrate (accepted in OFF).
    refused_in(&mut c, "OFF", &[&entries[..], &moving[..]].concat());

    // HOLD, not calibrated: the motion modes say so; the rest name the mode.
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    for (name, req) in commands() {
        if entries.contains(&name) {
            assert_error(
                &c.request(req),
                &[&format!("{name} refused"), "axis 1 is not calibrated"],
            );
        }
    }
    refused_in(&mut c, "HOLD", &moving);

    // CALIBRATION (seen from a second connection while the first waits for the reply). The
    // first one controls the arm, so the second one's motion commands are refused naming it
    // before any mode check (docs/protocol.md, "Control of the arm and access").
    let mut other = mcm.client();
    c.send_raw(b"{\"command\":\"calibrate\"}\n");
    other.wait_status("CALIBRATION", |s| s["operating_mode"] == "CALIBRATION");
    for (name, req) in commands() {
        if [&["calibrate"][..], &entries[..], &moving[..]]
            .concat()
            .contains(&name)
        {
            assert_error(
                &other.request(req),
                &[
                    &format!("{name} refused"),
                    "the arm is controlled by JSON client",
                ],
            );
        }
    }
    assert_status(&status(&mut other), "CALIBRATION");
    assert_ok(&c.recv());

    // HOLD, calibrated.
    refused_in(&mut c, "HOLD", &moving);
    let still = truth(&mut c).position;

    // PVT.
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    refused_in(
        &mut c,
        "PVT",
        &[
            "calibrate",
            "release",
            "pvt",
            "torque_control",
            "set_torques",
        ],
    );

    // RELEASE.
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    assert_status(&c.request(r#"{"command":"release"}"#), "RELEASE");
    refused_in(
        &mut c,
        "RELEASE",
        &[&["calibrate"][..], &entries[..], &moving[..]].concat(),
    );

    // TORQUE_CONTROL (no timeout).
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    assert_status(
        &c.request(r#"{"command":"torque_control","arguments":{"timeout":-1}}"#),
        "TORQUE_CONTROL",
    );
    refused_in(
        &mut c,
        "TORQUE_CONTROL",
        &[
            "calibrate",
            "release",
            "pvt",
            "torque_control",
            "move_axis",
            "move_all",
            "pvt_points",
        ],
    );
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    // Nothing refused moved the arm.
    let t = wait_at_rest(&mut c).position;
    assert!(max_diff(&still, &t) < 0.1, "{still:?} -> {t:?}");
}

// ---------------------------------------------------------------------------------------------
// 8. which values status reports in each mode

#[test]
fn status_reports_commanded_positions_in_pvt_and_commanded_currents_in_torque_modes() {
    let cfg = config();
    let rated: [f64; 6] = std::array::from_fn(|i| cfg.axes[i].rated_current_a);
    let on_grid = |cur: &[f64; 6]| (0..6).all(|i| on_drive_grid(cur[i], rated[i]));
    let (_mcm, mut c) = calibrated("status-modes");

    // HOLD: everything measured: positions are the measured ones (and the truth), currents
    // are what the drives measure (per-mille of their rated current).
    let t = wait_at_rest(&mut c);
    let s = detail(&mut c);
    assert_eq!(position(&s), detail6(&s, "measured_position"), "{s}");
    assert!(max_diff(&position(&s), &t.position) < 0.05, "{s}");
    assert!(on_grid(&current(&s)), "measured currents: {s}");

    // PVT: positions (and velocities) commanded, currents measured. While moving, the
    // commanded position leads the measured one.
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    assert_ok(&c.request(&move_axis(1, 30.0, 1.0)));
    let mut lead: f64 = 0.0;
    let mut fastest: f64 = 0.0;
    let deadline = Instant::now() + WAIT;
    loop {
        let s = detail(&mut c);
        assert_status(&s, "PVT");
        assert_eq!(position(&s), detail6(&s, "commanded_position"), "{s}");
        assert!(on_grid(&current(&s)), "measured currents in PVT: {s}");
        lead = lead.max(position(&s)[0] - detail6(&s, "measured_position")[0]);
        fastest = fastest.max(velocity(&s)[0]);
        if position(&s)[0] == 30.0 && velocity(&s)[0] == 0.0 {
            break;
        }
        assert!(Instant::now() < deadline, "move did not end: {s}");
        std::thread::sleep(POLL_PAUSE);
    }
    assert!(
        lead > 0.05,
        "the commanded position leads the measured one by {lead}"
    );
    assert!(
        fastest > 30.0 && fastest <= 90.0 + 1e-6,
        "the commanded velocity of axis 1 at factor 1 (its maximum 90 deg/s): {fastest}"
    );
    // Put gravity to work for the torque modes.
    move_to(&mut c, &[30.0, 30.0, 30.0, 0.0, 20.0, 0.0]);

    // RELEASE: positions and velocities measured, currents commanded (gravity compensation
    // at full resolution, not on the drives' measuring grid).
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    let held = detail(&mut c);
    assert!(on_grid(&current(&held)), "{held}");
    assert_status(&c.request(r#"{"command":"release"}"#), "RELEASE");
    wait_at_rest(&mut c);
    let s = detail(&mut c);
    let t = truth(&mut c);
    assert_eq!(position(&s), detail6(&s, "measured_position"), "{s}");
    assert!(max_diff(&position(&s), &t.position) < 0.05, "{s}");
    assert!(max_diff(&velocity(&s), &t.velocity) < 1.0, "{s}");
    assert!(!on_grid(&current(&s)), "commanded currents in RELEASE: {s}");
    let release_currents = current(&s);
    // The shoulder carries the arm: its current says so, in both modes.
    assert!(
        current(&held)[1].abs() > 0.1 && release_currents[1].abs() > 0.1,
        "gravity on axis 2: held {held}, released {s}"
    );

    // TORQUE_CONTROL with zero torques: the same compensation, commanded.
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    assert_status(
        &c.request(r#"{"command":"torque_control","arguments":{"timeout":-1}}"#),
        "TORQUE_CONTROL",
    );
    // set_torques has no result on success: the next result is the status's.
    c.send_raw(format!("{ZERO_TORQUES}\n").as_bytes());
    wait_at_rest(&mut c);
    let s = detail(&mut c);
    assert_status(&s, "TORQUE_CONTROL");
    assert_eq!(position(&s), detail6(&s, "measured_position"), "{s}");
    assert!(
        !on_grid(&current(&s)),
        "commanded currents in TORQUE_CONTROL: {s}"
    );
    assert!(
        max_diff(&current(&s), &release_currents) < 0.1,
        "zero torques: the compensation of RELEASE: {s}"
    );
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
}
