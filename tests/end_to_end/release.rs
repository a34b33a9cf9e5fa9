//! End to end: RELEASE's soft speed limit, the drive's loop after a following-error trip
//! against an obstacle, a power cycle naming every axis, and a `position_limit` trip; each
//! against the simulation's ground truth (`sim`: `true_position`, `true_velocity`).
//!
//! Every wait is bounded; the short pauses in polling loops only pace the polls. Robot times are
//! the `time` of status results.

use crate::common;

use common::{
    EventClient, Mcm, WAIT, assert_ok, assert_status, config_file, is_event, max_diff, six, time_of,
};
use serde_json::{Value, json};
use std::time::{Duration, Instant};

const STATUS_DETAIL: &str = r#"{"command":"status","arguments":{"detail":true}}"#;
/// Calibration takes about 12 s of robot time; allow for a loaded machine.
const CALIBRATION_WAIT: Duration = Duration::from_secs(90);
const POLL_PAUSE: Duration = Duration::from_millis(5);

/// What these tests ask of the simulated arm, over a connection that keeps spontaneous safety
/// errors apart from replies.
pub(crate) trait Arm {
    fn detail(&mut self) -> Value;
    fn sim(&mut self, args: Value) -> ([f64; 6], [f64; 6]);
    fn truth(&mut self) -> ([f64; 6], [f64; 6]);
    fn wait_until(
        &mut self,
        what: &str,
        done: impl FnMut(&Value, &[f64; 6], &[f64; 6]) -> bool,
    ) -> (Value, [f64; 6], [f64; 6]);
    fn observe(&mut self, seconds: f64, each: impl FnMut(&Value, &[f64; 6], &[f64; 6]));
    fn wait_drives_online(&mut self);
    fn calibrate(&mut self);
}

impl Arm for EventClient {
    fn detail(&mut self) -> Value {
        let s = self.request(STATUS_DETAIL);
        assert_eq!(s["result_type"], "status", "{s}");
        s
    }

    /// `sim` with `args`: the true positions and velocities [deg, deg/s].
    fn sim(&mut self, args: Value) -> ([f64; 6], [f64; 6]) {
        let r = self.request(&json!({"command": "sim", "arguments": args}).to_string());
        assert_eq!(r["result_type"], "sim", "{r}");
        (six(&r["true_position"]), six(&r["true_velocity"]))
    }

    fn truth(&mut self) -> ([f64; 6], [f64; 6]) {
        let r = self.request(r#"{"command":"sim"}"#);
        assert_eq!(r["result_type"], "sim", "{r}");
        (six(&r["true_position"]), six(&r["true_velocity"]))
    }

    /// Poll the detailed status and the truth until `done`; panics after [`WAIT`].
    fn wait_until(
        &mut self,
        what: &str,
        mut done: impl FnMut(&Value, &[f64; 6], &[f64; 6]) -> bool,
    ) -> (Value, [f64; 6], [f64; 6]) {
        let deadline = Instant::now() + WAIT;
        loop {
            let s = self.detail();
            let (q, v) = self.truth();
            if done(&s, &q, &v) {
                return (s, q, v);
            }
            assert!(
                Instant::now() < deadline,
                "timed out waiting for {what}: {s}"
            );
            std::thread::sleep(POLL_PAUSE);
        }
    }

    /// Poll for `seconds` of robot time, calling `each` with the status and the truth.
    fn observe(&mut self, seconds: f64, mut each: impl FnMut(&Value, &[f64; 6], &[f64; 6])) {
        let t0 = time_of(&self.detail());
        let deadline = Instant::now() + WAIT;
        loop {
            let s = self.detail();
            let (q, v) = self.truth();
            each(&s, &q, &v);
            if time_of(&s) >= t0 + seconds {
                return;
            }
            assert!(Instant::now() < deadline, "robot time stands still: {s}");
            std::thread::sleep(POLL_PAUSE);
        }
    }

    fn wait_drives_online(&mut self) {
        self.wait_until("every drive online", |s, _, _| {
            s["detail"]["drive_online"]
                .as_array()
                .is_some_and(|a| a.iter().all(|x| x == true))
        });
    }

    fn calibrate(&mut self) {
        let r = self.request_within(r#"{"command":"calibrate"}"#, CALIBRATION_WAIT);
        assert_ok(&r);
        assert_status(&self.detail(), "HOLD");
    }
}

/// The spontaneous error of a tripped check: its check, axis and words.
fn assert_event(e: &Value, check: &str, axis: Option<u64>, words: &[&str]) {
    assert!(is_event(e), "not a spontaneous error: {e}");
    assert_eq!(e["check"], check, "{e}");
    assert_eq!(
        e["error_code"], check,
        "a safety error's code is its check: {e}"
    );
    assert_eq!(e["axis"].as_u64(), axis, "{e}");
    let msg = e["error_message"].as_str().unwrap_or_default();
    for w in words {
        assert!(msg.contains(w), "{msg:?} lacks {w:?}");
    }
}

fn torques(axis: usize, nm: f64) -> Value {
    let mut t = [0.0; 6];
    t[axis] = nm;
    json!({ "external_torques": t })
}

#[test]
fn a_push_in_release_is_slowed_below_the_velocity_limit_until_the_hard_check_is_needed() {
    let mcm = Mcm::start("release-push");
    let mut c = EventClient::connect(mcm.json);
    c.wait_drives_online();
    c.calibrate();
    assert_status(&c.request(r#"{"command":"release"}"#), "RELEASE");
    let limit = 90.0;
    let mut sign = 1.0;
    for nm in [4.0, 6.0, 8.0, 10.0] {
        c.sim(torques(0, sign * nm));
        let mut peak: f64 = 0.0;
        c.observe(0.7, |s, _, v| {
            assert_status(s, "RELEASE");
            peak = peak.max(v[0].abs());
        });
        c.sim(torques(0, 0.0));
        let (_, q, _) = c.wait_until("axis 1 at rest", |_, _, v| {
            peak = peak.max(v[0].abs());
            v[0].abs() < 0.5
        });
        eprintln!(
            "RELEASE: axis 1 pushed with {nm} Nm for 0.7 s: true speed peaked at {peak:.1} deg/s (limit {limit}), rests at {:.1} deg",
            q[0]
        );
        assert!(peak < limit, "{nm} Nm: {peak} deg/s");
        assert!(c.events.is_empty(), "{nm} Nm: no trip: {:?}", c.events);
        assert_status(&c.detail(), "RELEASE");
        sign = -sign;
    }
    // Beyond what the damping can catch: the hard check is the last resort.
    c.sim(torques(0, sign * 40.0));
    let e = c.wait_event("a trip", WAIT);
    assert_event(&e, "velocity_limit", Some(1), &["velocity limit: axis 1"]);
    c.sim(torques(0, 0.0));
    let (s, _, _) = c.wait_until("the arm at rest", |_, _, v| v.iter().all(|x| x.abs() < 0.5));
    assert_status(&s, "ERROR");
    eprintln!("RELEASE: 40 Nm: {}", e["error_message"]);
}

#[test]
fn after_a_following_error_trip_against_an_obstacle_the_drive_stops_pressing() {
    let mcm = Mcm::start("release-obstacle");
    let mut c = EventClient::connect(mcm.json);
    c.wait_drives_online();
    c.calibrate();
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    let mv = json!({"command": "move_axis", "arguments":
        {"axis_index": 1, "target_position": 60.0, "velocity_factor": 0.5}});
    assert_ok(&c.request(&mv.to_string()));
    c.wait_until("axis 1 moving", |_, _, v| v[0] > 10.0);
    c.sim(json!({"block_axis": 1}));
    let e = c.wait_event("a trip", WAIT);
    assert_event(&e, "following_error", Some(1), &["following error: axis 1"]);
    let mut current = Vec::new();
    c.observe(0.5, |s, _, _| {
        assert_status(s, "ERROR");
        current.push(six(&s["axis_states"]["current"])[0]);
    });
    let last = current[current.len() - 1];
    eprintln!("obstacle: 0.5 s after the trip the drive of axis 1 draws {last:.2} A");
    // Without the restart it pressed with the full 10 A until `hold`; about 1 A is left (the
    // loop holding the axis against the obstacle's spring where it came to rest).
    assert!(
        last.abs() < 2.5,
        "not pressing into the obstacle: {current:?}"
    );
    let (stands, _) = c.truth();
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    c.sim(json!({"unblock_axis": 1}));
    let mut jump: f64 = 0.0;
    c.observe(0.5, |s, q, _| {
        assert_status(s, "HOLD");
        jump = jump.max((q[0] - stands[0]).abs());
    });
    eprintln!("obstacle: after hold and unblock axis 1 moved up to {jump:.4} deg");
    assert!(jump < 0.05, "no spring when the obstacle goes: {jump} deg");
}

#[test]
fn a_power_cycle_names_every_axis_it_affected() {
    let mcm = Mcm::start("release-power");
    let mut c = EventClient::connect(mcm.json);
    c.wait_drives_online();
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    c.sim(json!({"power_cycle": true}));
    let e = c.wait_event("a trip", WAIT);
    eprintln!("power cycle: {}", e["error_message"]);
    assert_event(
        &e,
        "drive_disconnected",
        Some(1),
        &["the drives of axes 1, 2, 3, 4, 5 and 6 do not answer on the bus"],
    );
}

#[test]
fn a_push_beyond_a_joint_limit_in_release_trips_position_limit_and_the_arm_stops() {
    // The elbow's range 5..135 deg leaves out the zero calibration returns to.
    let cfg = config_file("release-limit", |t| {
        let t = t.replacen("min_deg = -135.0", "min_deg = 5.0", 1);
        t.replacen(
            "initial_position_deg = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]",
            "initial_position_deg = [0.0, 0.0, 10.0, 0.0, 0.0, 0.0]",
            1,
        )
    });
    let mcm = Mcm::start_with("release-limit", &["--config", cfg.path()]);
    let mut c = EventClient::connect(mcm.json);
    c.wait_drives_online();
    c.calibrate();
    let (_, q, _) = c.wait_until("the arm at rest", |_, _, v| {
        v.iter().all(|x| x.abs() < 0.01)
    });
    assert!(
        q[2].abs() < 0.1,
        "the elbow at zero, beyond its limit: {q:?}"
    );
    // The push starts in HOLD (the drives hold against it), so the arm moves outward from the
    // first cycle of RELEASE: an arm at rest beyond its limit trips as soon as its measured
    // velocity points further out, which noise alone can do, so the push decides, not noise.
    c.sim(torques(2, -20.0));
    // `release` is accepted (a refusal is a generic result with no mode); its state is RELEASE,
    // or already the trip's ERROR when the push crossed the limit within the cycle that
    // executed it (the trip itself is checked on the spontaneous error below).
    let r = c.request(r#"{"command":"release"}"#);
    assert_eq!(r["result_type"], "status", "release accepted: {r}");
    assert!(
        matches!(r["operating_mode"].as_str(), Some("RELEASE" | "ERROR")),
        "release entered (or the trip already reported): {r}"
    );
    let e = c.wait_event("a trip", WAIT);
    assert_event(
        &e,
        "position_limit",
        Some(3),
        &["position limit: axis 3 at", "limit 5.000 deg"],
    );
    eprintln!("position limit: {}", e["error_message"]);
    c.sim(torques(2, 0.0));
    let (s, q, _) = c.wait_until("the arm at rest", |_, _, v| {
        v.iter().all(|x| x.abs() < 0.01)
    });
    assert_status(&s, "ERROR");
    assert!(
        q[2] > -2.0,
        "the elbow stopped near where it tripped: {q:?}"
    );
}

#[test]
fn entering_hold_under_gravity_sags_less_than_0_02_deg() {
    let mcm = Mcm::start("release-sag");
    let mut c = EventClient::connect(mcm.json);
    c.wait_drives_online();
    c.calibrate();
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    let mv = json!({"command": "move_all", "arguments":
        {"target_positions": [0.0, 60.0, 30.0, 0.0, 30.0, 0.0], "velocity_factor": 0.5}});
    let r = c.request(&mv.to_string());
    assert_eq!(r["result_type"], "move_all", "{r}");
    let target = [0.0, 60.0, 30.0, 0.0, 30.0, 0.0];
    c.wait_until("the arm at the target, at rest", |_, q, v| {
        max_diff(q, &target) < 0.05 && v.iter().all(|x| x.abs() < 0.01)
    });
    // Let the loops settle on the target (they converge within a second).
    c.observe(1.0, |s, _, _| assert_status(s, "PVT"));
    let (at, _) = c.truth();
    // After the move.
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    let mut sag: f64 = 0.0;
    c.observe(1.0, |_, q, _| sag = sag.max(max_diff(q, &at)));
    eprintln!("HOLD after a move: the true arm moved up to {sag:.4} deg");
    assert!(sag < 0.02, "after a move: {sag} deg");
    // From RELEASE, at rest.
    assert_status(&c.request(r#"{"command":"release"}"#), "RELEASE");
    c.observe(1.0, |s, _, _| assert_status(s, "RELEASE"));
    let (before, _) = c.truth();
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    let mut sag: f64 = 0.0;
    c.observe(1.0, |_, q, _| sag = sag.max(max_diff(q, &before)));
    eprintln!("HOLD from RELEASE: the true arm moved up to {sag:.4} deg");
    assert!(sag < 0.02, "from RELEASE: {sag} deg");
}
