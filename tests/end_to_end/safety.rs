//! End to end: the safety checks of the manual ("Safety checks"), by fault injection over TCP.
//!
//! Every test starts the real launcher (mcm-rt + mcm-gateway) with a copy of
//! `deploy/prob2.toml` whose `safety.flight_recorder_dir` is a directory of its own, injects a
//! fault with `sim`, and checks
//! - the reaction the clients see: one spontaneous `generic` ERROR per incident naming the
//!   check and the axis, the mode `ERROR`, the commands refused while the cause persists;
//! - the reaction of the arm, on the simulation's ground truth (`sim`: `true_position`,
//!   `true_velocity`, `emergency_stop`), not only on what the MCM says about itself;
//! - the flight-recorder file the error names: header, one row per cycle of the last
//!   `safety.flight_recorder_seconds` (fewer if the MCM ran less long), the trip in its last
//!   row and the moments before it in the rows before;
//! - the recovery (`hold`).
//!
//! Every wait is bounded; the short pauses in polling loops only pace the polls. Robot times are
//! the `time` of status results (`CLOCK_MONOTONIC` of the cycle) and the `t_s` and `cycle`
//! columns of the flight recorder.

use crate::common;

use common::flight::Flight;
use common::{
    EventClient, Mcm, WAIT, assert_ok, assert_status, is_event, max_abs, max_diff, move_all,
    move_axis, six, time_of,
};
use mcm_shared::config::RobotConfig;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

const STATUS: &str = r#"{"command":"status"}"#;
const STATUS_DETAIL: &str = r#"{"command":"status","arguments":{"detail":true}}"#;
const HOLD: &str = r#"{"command":"hold"}"#;
/// No test here streams points.
const PVT: &str = common::PVT_ANY_RATE;
const RELEASE: &str = r#"{"command":"release"}"#;
const TORQUE_CONTROL: &str = r#"{"command":"torque_control","arguments":{"timeout":1.0,"dt_status":0,"gravity_compensation":true}}"#;
const ZERO_TORQUES: &str = r#"{"command":"set_torques","arguments":{"torques":[0,0,0,0,0,0]}}"#;
/// The three motion modes and the commands that enter them.
const MOTION_MODES: [(&str, &str); 3] = [
    ("PVT", PVT),
    ("RELEASE", RELEASE),
    ("TORQUE_CONTROL", TORQUE_CONTROL),
];
/// How late a poll over TCP may see an event that already happened [s].
const POLL_SLACK: f64 = 0.03;
/// Pause between polls (pacing only; every loop ends on an observed condition or a deadline).
const POLL_PAUSE: Duration = Duration::from_millis(5);
/// How soon after an emergency stop is pressed every client must be told, on the robot's clock
/// [s]: the press's way to the core, the trip a few cycles later, the error's way to each
/// connection, with room for a loaded machine.
const TOLD_WITHIN: f64 = 0.25;
/// Calibration takes about 12 s of robot time; allow for a loaded machine.
const CALIBRATION_WAIT: Duration = Duration::from_secs(60);
/// The checks the manual evaluates on position and velocity in the motion modes.
const LIMIT_CHECKS: [&str; 3] = ["braking_distance", "position_limit", "velocity_limit"];

// ---------------------------------------------------------------------------------------------
// The MCM under test, with a flight-recorder directory of its own

/// A running MCM started with a per-test copy of `deploy/prob2.toml`.
struct Rig {
    mcm: Option<Mcm>,
    cfg: RobotConfig,
    dir: PathBuf,
    flight_dir: PathBuf,
}

impl Rig {
    /// Write the configuration (flight recorder in a directory of this test) and start the MCM.
    fn start(tag: &str) -> Rig {
        let dir = std::env::temp_dir().join(format!("mcm-safety-{}-{tag}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create the test directory");
        let flight_dir = dir.join("flight");
        // deploy/prob2.toml as embedded (the test guest has the binaries, not the sources).
        let text = mcm_shared::config::PROB2_DEFAULT_TOML;
        let mut replaced = 0;
        let text: String = text
            .lines()
            .map(|l| {
                if l.trim_start().starts_with("flight_recorder_dir") {
                    replaced += 1;
                    format!("flight_recorder_dir = \"{}\"", flight_dir.display())
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n");
        assert_eq!(
            replaced, 1,
            "deploy/prob2.toml sets safety.flight_recorder_dir once"
        );
        let path = dir.join("prob2.toml");
        std::fs::write(&path, text + "\n").expect("write the test configuration");
        let cfg = RobotConfig::from_file(&path).expect("the test configuration is valid");
        assert_eq!(
            cfg.safety.flight_recorder_dir,
            flight_dir.display().to_string()
        );
        let mcm = Mcm::start_with(tag, &["--config", path.to_str().unwrap()]);
        // Over SocketCAN on an emulated machine the MCM runs another cycle rate and bus timing
        // (tests/common/virtual_arm.rs): the checks here go by what it runs.
        let cfg = match &mcm.arm {
            Some(arm) => RobotConfig::from_file(Path::new(arm.config.path()))
                .expect("the virtual arm's configuration is valid"),
            None => cfg,
        };
        Rig {
            mcm: Some(mcm),
            cfg,
            dir,
            flight_dir,
        }
    }

    fn mcm(&self) -> &Mcm {
        self.mcm.as_ref().expect("the MCM runs")
    }

    /// Whether the simulation runs inside the core. Over SocketCAN (the test guest) it runs in
    /// the virtual arm instead: the `sim` commands go there, and the flight recorder has neither
    /// their rows nor the truth, so the checks that need them are left out (the timing is also
    /// checked on the robot's clock from the clients' side).
    fn sim_in_core(&self) -> bool {
        self.mcm().arm.is_none()
    }

    fn conn(&self) -> EventClient {
        EventClient::connect(self.mcm().json)
    }

    /// Cycle period [s].
    fn cycle(&self) -> f64 {
        self.cfg.cycle_period_s()
    }

    /// Rows the flight recorder keeps: `flight_recorder_seconds * rate_hz`.
    fn flight_rows(&self) -> usize {
        (self.cfg.safety.flight_recorder_seconds * f64::from(self.cfg.cycle.rate_hz)).ceil()
            as usize
    }
}

impl Drop for Rig {
    fn drop(&mut self) {
        // Stop the MCM (its drop also removes the simulation it saved for a restart) before
        // the directory its flight recorder writes to goes.
        drop(self.mcm.take());
        if std::thread::panicking() {
            eprintln!("keeping {} for inspection", self.dir.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Helpers

fn bools(v: &Value) -> [bool; 6] {
    let a = v
        .as_array()
        .unwrap_or_else(|| panic!("expected an array of 6 booleans, got {v}"));
    assert_eq!(a.len(), 6, "expected 6 booleans, got {v}");
    std::array::from_fn(|i| a[i].as_bool().unwrap_or_else(|| panic!("not a bool: {v}")))
}

/// A generic ERROR (not a spontaneous one) whose message contains every one of `words`.
fn assert_refused(v: &Value, words: &[&str]) {
    assert!(
        v["result_type"] == "generic" && v["error_status"] == "ERROR",
        "expected a generic ERROR, got {v}"
    );
    let msg = v["error_message"].as_str().unwrap_or_default();
    for w in words {
        assert!(msg.contains(w), "error message {msg:?} lacks {w:?}");
    }
}

/// The ground truth of the simulated arm.
#[derive(Debug, Clone, Copy)]
struct Truth {
    position: [f64; 6],
    velocity: [f64; 6],
    emergency_stop: bool,
}

fn sim(c: &mut EventClient, args: Option<Value>) -> Truth {
    let cmd = match args {
        Some(a) => json!({"command": "sim", "arguments": a}).to_string(),
        None => r#"{"command":"sim"}"#.to_string(),
    };
    let r = c.request(&cmd);
    assert_eq!(r["result_type"], "sim", "{r}");
    Truth {
        position: six(&r["true_position"]),
        velocity: six(&r["true_velocity"]),
        emergency_stop: r["emergency_stop"]
            .as_bool()
            .unwrap_or_else(|| panic!("no emergency_stop in {r}")),
    }
}

fn truth(c: &mut EventClient) -> Truth {
    sim(c, None)
}

fn status(c: &mut EventClient) -> Value {
    let s = c.request(STATUS);
    assert_eq!(s["result_type"], "status", "{s}");
    s
}

fn detail(c: &mut EventClient) -> Value {
    let s = c.request(STATUS_DETAIL);
    assert_eq!(s["result_type"], "status", "{s}");
    s
}

/// Poll the detailed status and the truth until `done`; panics after `wait`.
fn wait_until_within(
    c: &mut EventClient,
    what: &str,
    wait: Duration,
    mut done: impl FnMut(&Value, &Truth) -> bool,
) -> (Value, Truth) {
    let deadline = Instant::now() + wait;
    loop {
        let s = detail(c);
        let t = truth(c);
        if done(&s, &t) {
            return (s, t);
        }
        assert!(
            Instant::now() < deadline,
            "timed out waiting for {what}; last status {s}; truth {t:?}"
        );
        std::thread::sleep(POLL_PAUSE);
    }
}

fn wait_until(
    c: &mut EventClient,
    what: &str,
    done: impl FnMut(&Value, &Truth) -> bool,
) -> (Value, Truth) {
    wait_until_within(c, what, WAIT, done)
}

/// Wait until the true arm is at rest (every true velocity below 0.01 deg/s).
fn wait_at_rest(c: &mut EventClient) -> Truth {
    wait_until(c, "the arm at rest", |_, t| max_abs(&t.velocity) < 0.01).1
}

/// Poll for `seconds` of robot time, calling `each` with the latest status and truth.
fn observe(c: &mut EventClient, seconds: f64, mut each: impl FnMut(&Value, &Truth)) {
    let t0 = time_of(&status(c));
    let deadline = Instant::now() + WAIT;
    loop {
        let s = detail(c);
        let t = truth(c);
        each(&s, &t);
        if time_of(&s) >= t0 + seconds {
            return;
        }
        assert!(Instant::now() < deadline, "robot time stands still: {s}");
        std::thread::sleep(POLL_PAUSE);
    }
}

fn wait_drives_online(c: &mut EventClient) {
    wait_until(c, "every drive online", |s, _| {
        bools(&s["detail"]["drive_online"]).iter().all(|x| *x)
    });
}

/// Calibrate every axis (from OFF or HOLD); the arm ends in HOLD at zero.
fn calibrate(c: &mut EventClient) {
    let r = c.request_within(r#"{"command":"calibrate"}"#, CALIBRATION_WAIT);
    assert_ok(&r);
    let s = detail(c);
    assert_status(&s, "HOLD");
    assert_eq!(bools(&s["detail"]["calibrated"]), [true; 6], "{s}");
}

/// Send `hold` until it is accepted (it is refused while the cause of an error persists and
/// until the drives report that it is gone); returns the status result and the refusals.
fn hold_until_accepted(c: &mut EventClient) -> (Value, Vec<Value>) {
    let deadline = Instant::now() + WAIT;
    let mut refusals = Vec::new();
    loop {
        let r = c.request(HOLD);
        if r["result_type"] == "status" {
            return (r, refusals);
        }
        assert_refused(&r, &["hold"]);
        refusals.push(r);
        assert!(
            Instant::now() < deadline,
            "hold still refused after {WAIT:?}: {refusals:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The spontaneous error of a tripped check: its fields and words.
fn assert_event(e: &Value, check: &str, axis: Option<u64>) {
    assert!(is_event(e), "not a spontaneous error: {e}");
    assert_eq!(e["check"], check, "{e}");
    assert_eq!(
        e["error_code"], check,
        "a safety error's code is its check: {e}"
    );
    assert_eq!(e["axis"].as_u64(), axis, "{e}");
    let msg = e["error_message"].as_str().unwrap_or_default();
    assert!(
        msg.starts_with("safety check tripped: ") && msg.contains("mode is now ERROR"),
        "{msg:?}"
    );
    if let Some(a) = axis {
        assert!(msg.contains(&format!("axis {a}")), "{msg:?} names axis {a}");
    }
}

// ---------------------------------------------------------------------------------------------
// The flight recorder

/// The flight-recorder file named by the spontaneous error `e` of the first incident of this
/// MCM, once it is completely written; checks what every such file must hold.
fn flight(rig: &Rig, e: &Value, check: &str) -> Flight {
    flight_after(rig, e, check, None)
}

/// [`flight`] for any incident: `previous` is the file of the incident before, if any (the
/// recorder starts afresh after each file).
fn flight_after(rig: &Rig, e: &Value, check: &str, previous: Option<&Flight>) -> Flight {
    let file = e["flight_recorder"]
        .as_str()
        .unwrap_or_else(|| panic!("no flight_recorder in {e}"));
    let msg = e["error_message"].as_str().unwrap_or_default();
    assert!(
        msg.ends_with(&format!("flight recorder: {file}")),
        "the message names the file: {msg:?}"
    );
    let path = PathBuf::from(file);
    assert_eq!(
        path.parent(),
        Some(rig.flight_dir.as_path()),
        "written to safety.flight_recorder_dir"
    );
    let name = path.file_name().unwrap().to_str().unwrap();
    let prefix = format!("mcm-{}-", rig.mcm().instance);
    let suffix = format!("-{check}.csv");
    let ms = name
        .strip_prefix(&prefix)
        .and_then(|n| n.strip_suffix(&suffix))
        .unwrap_or_else(|| panic!("{name} is not {prefix}<unix ms>{suffix}"));
    assert!(
        ms.parse::<u64>().is_ok(),
        "{name}: {ms} is not a time in ms"
    );

    let f = Flight::read(&path);
    let mut expected = vec!["cycle", "t_s", "mode", "flags", "command"]
        .into_iter()
        .map(str::to_string)
        .collect::<Vec<_>>();
    for name in [
        "commanded_deg",
        "measured_deg",
        "velocity_deg_s",
        "current_a",
        "following_error_deg",
        "i2t",
        "sim_true_deg",
    ] {
        expected.extend((1..=6).map(|a| format!("{name}_{a}")));
    }
    assert_eq!(f.header, expected, "the header of {}", path.display());
    for (r, row) in f.rows.iter().enumerate() {
        assert_eq!(row.len(), f.header.len(), "row {r} of {}", f.path.display());
    }
    assert!(!f.rows.is_empty(), "{} has no rows", f.path.display());

    // One row per cycle, consecutive, ending with the trip: the last flight_recorder_seconds,
    // or everything since the start (or since the previous file).
    let cycles = f.column("cycle");
    for w in cycles.windows(2) {
        assert_eq!(
            w[1],
            w[0] + 1.0,
            "consecutive cycles in {}",
            f.path.display()
        );
    }
    let last_cycle = cycles[f.last()] as usize;
    let since = previous.map_or(0, |p| p.num(p.last(), "cycle") as usize);
    let expected_rows = rig.flight_rows().min(last_cycle - since);
    assert_eq!(
        f.rows.len(),
        expected_rows,
        "{} rows up to cycle {last_cycle} (recorder holds {})",
        f.rows.len(),
        rig.flight_rows()
    );
    let t = f.column("t_s");
    let span = t[f.last()] - t[0];
    let nominal = (f.rows.len() - 1) as f64 * rig.cycle();
    assert!(
        span >= nominal - 0.02 && span <= nominal + 2.0,
        "{} rows span {span:.3} s (nominal {nominal:.3} s)",
        f.rows.len()
    );
    assert_eq!(
        f.text(f.last(), "mode"),
        "ERROR",
        "the trip is the last row"
    );
    // Before the trip: no error (since the start, or since the recovery from the previous one).
    let from = if previous.is_some() { f.last() - 1 } else { 0 };
    for r in from..f.last() {
        assert_ne!(
            f.text(r, "mode"),
            "ERROR",
            "row {r}: no error before the trip in {}",
            f.path.display()
        );
    }
    eprintln!(
        "flight recorder {}: {} rows, cycles {}..={last_cycle}, {span:.3} s",
        f.path.display(),
        f.rows.len(),
        cycles[0]
    );
    f
}

// ---------------------------------------------------------------------------------------------
// 1. Emergency stop during a move

#[test]
fn emergency_stop_during_a_move_stops_the_arm_and_tells_every_client_once() {
    let rig = Rig::start("estop");
    let mut c = rig.conn();
    wait_drives_online(&mut c);
    calibrate(&mut c);
    // Two more clients, connected and served before the incident.
    let mut watchers = [rig.conn(), rig.conn()];
    for w in &mut watchers {
        assert_status(&status(w), "HOLD");
    }
    assert_status(&c.request(PVT), "PVT");
    let target = [60.0, 30.0, -30.0, 0.0, 0.0, 0.0];
    let r = c.request(&move_all(&target, 0.5));
    assert_eq!(r["result_type"], "move_all", "{r}");
    wait_until(&mut c, "the arm moving", |_, t| t.velocity[0] > 20.0);

    // The press, sent without waiting for its result: the watchers are polled at once. On the
    // robot's clock it is in force after the state of `before`.
    let before = time_of(&status(&mut c));
    let press = json!({"command": "sim", "arguments": {"emergency_stop": true}}).to_string();
    let pressed = if rig.sim_in_core() {
        c.send(&press);
        None
    } else {
        // The virtual arm answers at once; the press is in force from its next period.
        Some(c.request(&press))
    };
    // Both watchers polled in turn until each has its error: the last state one of them saw
    // without it bounds how late it was told, on the robot's clock (a slow test only polls
    // less often, which cannot make it look later).
    let mut untold: [Option<f64>; 2] = [None; 2];
    let deadline = Instant::now() + WAIT;
    while watchers.iter().any(|w| w.events.is_empty()) {
        for (i, w) in watchers.iter_mut().enumerate() {
            if w.events.is_empty() {
                let t = time_of(&status(w));
                if w.events.is_empty() {
                    untold[i] = Some(t);
                }
            }
        }
        assert!(
            Instant::now() < deadline,
            "no emergency-stop error within {WAIT:?}: {untold:?}"
        );
        std::thread::sleep(POLL_PAUSE);
    }
    for (i, w) in watchers.iter_mut().enumerate() {
        let e = w.wait_event("emergency stop", WAIT);
        assert_event(&e, "emergency_stop", None);
        let late = untold[i].map_or(0.0, |t| t - before);
        eprintln!("estop: watcher {i} told within {late:.3} s (robot time) of the press");
        assert!(
            late < TOLD_WITHIN,
            "watcher {i}: still no error {late:.3} s (robot time) after the state before the \
             press; allowed {TOLD_WITHIN} s"
        );
    }
    let at_press = pressed.unwrap_or_else(|| c.result_within(&press, WAIT));
    assert_eq!(at_press["result_type"], "sim", "{at_press}");
    assert_eq!(at_press["emergency_stop"], true, "{at_press}");
    let at_press = six(&at_press["true_position"]);
    // One error per incident and client, nothing more: watched for 0.5 s of robot time.
    observe(&mut c, 0.5, |_, _| {});
    for (i, w) in watchers.iter_mut().enumerate() {
        let more = w.gather(Duration::from_millis(50));
        assert!(
            more.is_empty() && w.events.len() == 1,
            "watcher {i}: one error per incident, nothing more: {:?} {more:?}",
            w.events
        );
        assert!(w.unasked.is_empty(), "{:?}", w.unasked);
    }

    // The arm stops (brakes and STO) and stays still.
    let (s, rest) = wait_until(&mut c, "the arm at rest", |_, t| {
        max_abs(&t.velocity) < 1e-3
    });
    assert_status(&s, "ERROR");
    assert_eq!(s["detail"]["emergency_stop"], true, "{s}");
    assert!(
        s["hardware_status"]
            .as_str()
            .unwrap_or_default()
            .contains("emergency stop PRESSED"),
        "{s}"
    );
    let travel = max_diff(&rest.position, &at_press);
    eprintln!("estop: the arm travelled {travel:.3} deg after the press, at rest at {rest:?}");
    assert!(
        rest.position[0] < target[0] - 10.0 && travel < 5.0,
        "the move did not go on: {:?} -> {:?}",
        at_press,
        rest.position
    );
    observe(&mut c, 0.5, |s, t| {
        assert_status(s, "ERROR");
        assert!(t.emergency_stop);
        assert!(
            max_diff(&t.position, &rest.position) < 1e-3,
            "the braked arm stays still: {:?} -> {:?}",
            rest.position,
            t.position
        );
    });

    // hold is refused while the switch is pressed, and nothing moves.
    let r = c.request(HOLD);
    assert_refused(&r, &["hold refused", "emergency stop is pressed"]);
    assert_status(&status(&mut c), "ERROR");
    let still = truth(&mut c);
    assert!(max_diff(&still.position, &rest.position) < 1e-3);

    // Released: hold is accepted again (after the drives report the switch released).
    assert!(!sim(&mut c, Some(json!({"emergency_stop": false}))).emergency_stop);
    let (s, refusals) = hold_until_accepted(&mut c);
    assert_status(&s, "HOLD");
    for r in &refusals {
        assert_refused(r, &["emergency stop"]);
    }
    let s = wait_until(&mut c, "drives enabled", |s, _| {
        bools(&s["detail"]["drive_enabled"]) == [true; 6]
    })
    .0;
    assert_status(&s, "HOLD");
    assert_eq!(s["detail"]["emergency_stop"], false, "{s}");
    let after = wait_at_rest(&mut c);
    assert!(
        max_diff(&after.position, &rest.position) < 0.1,
        "re-enabled where it stood: {:?} -> {:?}",
        rest.position,
        after.position
    );

    // One spontaneous error per client for the whole incident.
    assert_eq!(c.events.len(), 1, "{:?}", c.events);
    assert_event(&c.events[0], "emergency_stop", None);
    for w in &mut watchers {
        assert!(w.gather(Duration::from_millis(100)).is_empty());
    }

    // The flight recorder: the move, then the trip a few cycles after the press.
    let f = flight(&rig, &c.events[0], "emergency_stop");
    let n = f.last();
    if !rig.sim_in_core() {
        return;
    }
    let press = f.last_sim_before_trip();
    eprintln!("estop: pressed in row {press}, tripped in row {n}");
    assert!(
        n - press <= 4,
        "tripped {} cycles after the press",
        n - press
    );
    for r in n.saturating_sub(20)..n {
        assert_eq!(
            f.text(r, "mode"),
            "PVT",
            "row {r}: moving in PVT before the trip"
        );
    }
    assert!(
        f.num(n - 1, "velocity_deg_s_1") > 10.0,
        "commanded velocity before the trip"
    );
    let moved = f.num(press, "sim_true_deg_1") - f.num(press - 10, "sim_true_deg_1");
    assert!(
        moved > 0.5,
        "the true arm moved in the rows before the press: {moved}"
    );
}

// ---------------------------------------------------------------------------------------------
// 2. Obstacle

#[test]
fn an_obstacle_trips_the_following_error_and_nothing_moves_afterwards() {
    let rig = Rig::start("obstacle");
    let mut c = rig.conn();
    wait_drives_online(&mut c);
    calibrate(&mut c);
    let band = rig.cfg.axes[0].following_error_deg;
    assert_status(&c.request(PVT), "PVT");
    let start = wait_at_rest(&mut c);
    assert_ok(&c.request(&move_axis(1, 60.0, 0.5)));
    wait_until(&mut c, "axis 1 moving", |_, t| t.velocity[0] > 10.0);
    let blocked = sim(&mut c, Some(json!({"block_axis": 1})));

    let e = c.wait_event("following error", WAIT);
    assert_event(&e, "following_error", Some(1));
    let msg = e["error_message"].as_str().unwrap();
    assert!(
        msg.contains("following error: axis 1") && msg.contains(&format!("band {band:.3} deg")),
        "{msg:?}"
    );
    assert_status(&status(&mut c), "ERROR");

    // No further motion: moves are refused, the arm comes to rest and stays.
    for cmd in [
        move_axis(2, 10.0, 0.5),
        move_all(&[0.0, 10.0, 0.0, 0.0, 0.0, 0.0], 0.5),
    ] {
        assert_refused(&c.request(&cmd), &["refused", "not allowed in mode ERROR"]);
    }
    let rest = wait_at_rest(&mut c);
    assert!(
        (rest.position[0] - blocked.position[0]).abs() < 0.5,
        "axis 1 held by the obstacle: {} -> {}",
        blocked.position[0],
        rest.position[0]
    );
    for a in 1..6 {
        assert!(
            (rest.position[a] - start.position[a]).abs() < 0.05,
            "axis {} did not move: {start:?} -> {rest:?}",
            a + 1
        );
    }
    // After the trip the axis relaxes off the obstacle (its drive's loop is restarted, so it
    // stops pressing): the last hundredths of a degree settle before nothing may move.
    let mut since: Option<(f64, [f64; 6])> = None;
    let (_, rest) = wait_until(&mut c, "the arm settled", |s, t| {
        let now = time_of(s);
        match since {
            Some((t0, p0)) if now - t0 >= 0.2 => {
                since = Some((now, t.position));
                max_diff(&t.position, &p0) < 0.002
            }
            Some(_) => false,
            None => {
                since = Some((now, t.position));
                false
            }
        }
    });
    let mut pressing = Vec::new();
    observe(&mut c, 0.5, |s, t| {
        pressing.push(six(&s["axis_states"]["current"])[0]);
        assert_status(s, "ERROR");
        assert!(
            max_diff(&t.position, &rest.position) < 0.01,
            "no further motion: {:?} -> {:?}",
            rest.position,
            t.position
        );
    });

    // What the drive of axis 1 does against the obstacle in ERROR (reported, not asserted).
    let cmd_error = six(&detail(&mut c)["detail"]["commanded_position"])[0];
    eprintln!(
        "obstacle: in ERROR axis 1 is commanded to {cmd_error:.3} deg, stands at {:.3} deg; motor current {:.2} A -> {:.2} A over 0.5 s",
        rest.position[0],
        pressing[0],
        pressing[pressing.len() - 1]
    );

    // Recovery: hold (nothing blocks it) holds where the arm stands; then the obstacle goes.
    let (s, refusals) = hold_until_accepted(&mut c);
    assert_status(&s, "HOLD");
    assert!(refusals.is_empty(), "{refusals:?}");
    let cmd_hold = six(&detail(&mut c)["detail"]["commanded_position"]);
    assert!(
        max_diff(&cmd_hold, &rest.position) < 0.5,
        "hold commands the position where the arm stands: {cmd_hold:?} vs {:?}",
        rest.position
    );
    sim(&mut c, Some(json!({"unblock_axis": 1})));
    let mut jump: f64 = 0.0;
    observe(&mut c, 0.5, |s, t| {
        assert_status(s, "HOLD");
        jump = jump.max(max_diff(&t.position, &rest.position));
        assert!(
            jump < band,
            "unblocked, held within the following band: {:?} -> {:?}",
            rest.position,
            t.position
        );
    });
    let settled = wait_at_rest(&mut c);
    eprintln!(
        "obstacle: after hold and unblock the arm moved up to {jump:.3} deg, settled {:.3} deg from where it stood",
        max_diff(&settled.position, &rest.position)
    );
    assert!(max_diff(&settled.position, &rest.position) < 0.1);
    assert_eq!(c.events.len(), 1, "{:?}", c.events);

    // The flight recorder: the following error of axis 1 grows from the block to the trip
    // while the true axis stands at the obstacle.
    let f = flight(&rig, &e, "following_error");
    let n = f.last();
    if !rig.sim_in_core() {
        return;
    }
    let block = f.last_sim_before_trip();
    eprintln!(
        "obstacle: blocked in row {block}, tripped in row {n}; following error {:?}",
        &f.column("following_error_deg_1")[block..=n]
    );
    assert!(n > block, "the trip comes after the block");
    assert!(f.num(block, "following_error_deg_1").abs() < 0.5);
    assert!(f.num(n, "following_error_deg_1").abs() > band);
    let fe: Vec<f64> = f.column("following_error_deg_1")[n.saturating_sub(5).max(block)..=n]
        .iter()
        .map(|x| x.abs())
        .collect();
    assert!(
        fe.windows(2).all(|w| w[1] > w[0]),
        "the following error grows in the last rows: {fe:?}"
    );
    for r in block..=n {
        assert!(
            (f.num(r, "sim_true_deg_1") - blocked.position[0]).abs() < 0.5,
            "row {r}: the true axis stands at the obstacle"
        );
        assert_eq!(f.text(r, "mode") == "PVT", r < n, "row {r}");
    }
    assert!(
        f.num(n - 1, "commanded_deg_1") - f.num(block, "commanded_deg_1") > band,
        "the command went on until the trip"
    );
}

// ---------------------------------------------------------------------------------------------
// 3. Silent drive

#[test]
fn a_silent_drive_trips_within_the_heartbeat_timeout_and_blocks_hold_until_it_is_back() {
    let rig = Rig::start("silent");
    let mut c = rig.conn();
    wait_drives_online(&mut c);
    assert_status(&c.request(HOLD), "HOLD");
    let before = wait_at_rest(&mut c);
    let timeout = f64::from(rig.cfg.bus.heartbeat_timeout_ms) / 1e3;
    let bound = timeout + 4.0 * rig.cycle();

    let t0 = time_of(&status(&mut c));
    sim(&mut c, Some(json!({"disconnect_axis": 3})));
    let deadline = Instant::now() + WAIT;
    let s = loop {
        let s = status(&mut c);
        if s["operating_mode"] != "HOLD" {
            break s;
        }
        assert!(Instant::now() < deadline, "still HOLD: {s}");
        std::thread::sleep(Duration::from_millis(2));
    };
    assert_status(&s, "ERROR");
    let seen = time_of(&s) - t0;
    eprintln!("silent drive: ERROR seen {seen:.3} s after the disconnect");
    assert!(
        seen <= bound + POLL_SLACK,
        "ERROR {seen:.3} s after the disconnect (heartbeat timeout {timeout} s + 4 cycles)"
    );
    let e = c.wait_event("drive disconnected", WAIT);
    assert_event(&e, "drive_disconnected", Some(3));
    assert!(
        e["error_message"]
            .as_str()
            .unwrap()
            .contains("the drive of axis 3 does not answer on the bus"),
        "{e}"
    );
    let s = detail(&mut c);
    assert_eq!(s["detail"]["drive_online"][2], false, "{s}");

    // hold is refused while the drive is silent, also after the heartbeat timeout.
    assert_refused(
        &c.request(HOLD),
        &["hold refused", "axis 3", "does not answer"],
    );
    observe(&mut c, 2.0 * timeout, |s, _| assert_status(s, "ERROR"));
    assert_refused(
        &c.request(HOLD),
        &["hold refused", "axis 3", "does not answer"],
    );
    let during = wait_at_rest(&mut c);
    assert!(
        max_diff(&during.position, &before.position) < 0.5,
        "the arm stays (brakes): {:?} -> {:?}",
        before.position,
        during.position
    );

    // Back on the bus: hold is accepted again and every drive is enabled.
    sim(&mut c, Some(json!({"reconnect_axis": 3})));
    let (s, refusals) = hold_until_accepted(&mut c);
    assert_status(&s, "HOLD");
    for r in &refusals {
        assert_refused(r, &["axis 3"]);
    }
    let s = wait_until(&mut c, "every drive enabled", |s, _| {
        bools(&s["detail"]["drive_enabled"]) == [true; 6]
    })
    .0;
    assert_status(&s, "HOLD");
    let after = wait_at_rest(&mut c);
    assert!(
        max_diff(&after.position, &before.position) < 0.5,
        "{:?} -> {:?}",
        before.position,
        after.position
    );
    assert_eq!(
        c.events.len(),
        1,
        "one error for the incident: {:?}",
        c.events
    );

    // The flight recorder: HOLD until the trip, which came within the timeout of the sim
    // command (counted in cycles).
    let f = flight(&rig, &e, "drive_disconnected");
    let n = f.last();
    if !rig.sim_in_core() {
        return;
    }
    let cut = f.last_sim_before_trip();
    let latency = (n - cut) as f64 * rig.cycle();
    eprintln!("silent drive: disconnected in row {cut}, tripped in row {n} ({latency:.3} s)");
    assert!(
        latency > 0.0 && latency <= bound,
        "detected after {latency:.3} s"
    );
    for r in cut..n {
        assert_eq!(f.text(r, "mode"), "HOLD", "row {r}");
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Torque towards a limit

/// What one push towards the limit did.
struct Push {
    event: Value,
    check: String,
    /// Highest and fastest true position [deg] and velocity [deg/s] of the axis, polled
    /// throughout.
    highest: f64,
    fastest: f64,
    /// Highest true position [deg] in the flight recorder (every cycle up to the trip).
    recorded: f64,
    flight: Flight,
}

/// From HOLD: move `axis` to `start_deg`, enter TORQUE_CONTROL (gravity compensation, zero
/// torques kept coming from the session's connection), push the axis towards its upper limit
/// with `push_nm` until a check trips and the arm stands still, take the push away and recover
/// with `hold`.
fn push_towards_the_limit(
    rig: &Rig,
    c: &mut EventClient,
    axis: usize,
    start_deg: f64,
    push_nm: f64,
    previous: Option<&Flight>,
) -> Push {
    assert_status(&c.request(PVT), "PVT");
    assert_ok(&c.request(&move_axis(axis, start_deg, 1.0)));
    wait_until(c, "the start position", |s, t| {
        max_abs(&six(&s["axis_states"]["velocity"])) == 0.0
            && (t.position[axis - 1] - start_deg).abs() < 0.05
            && max_abs(&t.velocity) < 0.01
    });
    assert_status(&c.request(HOLD), "HOLD");

    // The torque session runs on its own connection: the first hands control over.
    assert_ok(&c.request(r#"{"command":"release_control"}"#));
    let mut session = rig.conn();
    assert_status(&session.request(TORQUE_CONTROL), "TORQUE_CONTROL");
    session.send(ZERO_TORQUES);
    let events_before = c.events.len();
    let mut push = [0.0; 6];
    push[axis - 1] = push_nm;
    sim(c, Some(json!({"external_torques": push})));
    let deadline = Instant::now() + WAIT;
    let mut highest = f64::MIN;
    let mut fastest: f64 = 0.0;
    let mut polls = 0;
    loop {
        let tripped = c.events.len() > events_before;
        if !tripped {
            session.send(ZERO_TORQUES);
        }
        let t = truth(c);
        polls += 1;
        highest = highest.max(t.position[axis - 1]);
        fastest = fastest.max(t.velocity[axis - 1]);
        if tripped && max_abs(&t.velocity) < 0.01 {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "no trip, or no standstill: {t:?}"
        );
    }
    let event = c.events[events_before].clone();
    let check = event["check"].as_str().unwrap_or_default().to_string();
    eprintln!(
        "push {push_nm} Nm from {start_deg} deg: {check:?} tripped ({}); highest true position {highest:.3} deg, fastest {fastest:.1} deg/s ({polls} polls)",
        event["error_message"]
    );
    assert!(LIMIT_CHECKS.contains(&check.as_str()), "{event}");
    assert_event(&event, &check, Some(axis as u64));
    // The message names the limit the check compares with (from the configuration).
    let a = &rig.cfg.axes[axis - 1];
    let s = &rig.cfg.safety;
    let limit = match check.as_str() {
        "braking_distance" => format!("beyond the limit {:.3} deg", a.max_deg - s.limit_margin_deg),
        "velocity_limit" => format!(
            "limit {:.3} deg/s",
            s.overspeed_factor * a.max_velocity_deg_s
        ),
        _ => format!("limit {:.3} deg", a.max_deg),
    };
    assert!(
        event["error_message"].as_str().unwrap().contains(&limit),
        "{event} names {limit:?}"
    );
    assert_status(&status(c), "ERROR");

    // The session hears of it too, and that torque control is over.
    let se = session.wait_event("the trip", WAIT);
    assert_eq!(se["check"], check.as_str(), "{se}");
    let deadline = Instant::now() + WAIT;
    while !session
        .unasked
        .iter()
        .any(|v| v["result_type"] == "status" && v["operating_mode"] == "ERROR")
    {
        let left = deadline.saturating_duration_since(Instant::now());
        let v = session
            .next(left)
            .unwrap_or_else(|| panic!("no status leaving TORQUE_CONTROL: {:?}", session.unasked));
        session.unasked.push(v);
    }

    // The flight recorder: the axis was moving towards the limit in TORQUE_CONTROL right
    // before the trip.
    let flight = flight_after(rig, &event, &check, previous);
    let n = flight.last();
    assert_eq!(flight.text(n - 1, "mode"), "TORQUE_CONTROL");
    let v = flight.num(n, &format!("velocity_deg_s_{axis}"));
    assert!(v > 10.0, "moving towards the limit at the trip: {v} deg/s");
    // The truth as the core recorded it; over SocketCAN (no truth in the core) the position
    // the drive measured, the truth as its encoder saw it.
    let column = if rig.sim_in_core() {
        "sim_true_deg"
    } else {
        "measured_deg"
    };
    let recorded = flight
        .column(&format!("{column}_{axis}"))
        .into_iter()
        .fold(f64::MIN, f64::max);

    // The session's connection ends, and control of the arm with it.
    drop(session);
    wait_until(c, "control released after the session ended", |s, _| {
        s["detail"]["control"]["owner_client_id"].as_u64() == Some(0)
    });

    // The push goes; the arm stays where it stopped, and hold recovers.
    sim(c, Some(json!({"external_torques": [0, 0, 0, 0, 0, 0]})));
    let (s, _) = hold_until_accepted(c);
    assert_status(&s, "HOLD");
    assert_eq!(c.events.len(), events_before + 1, "{:?}", c.events);
    Push {
        event,
        check,
        highest,
        fastest,
        recorded,
        flight,
    }
}

#[test]
fn a_torque_driving_an_axis_towards_its_limit_is_stopped_before_the_limit() {
    const AXIS: usize = 1;
    const START_DEG: f64 = 150.0;
    let rig = Rig::start("torque-limit");
    let limit = rig.cfg.axes[AXIS - 1].max_deg;
    let mut c = rig.conn();
    wait_drives_online(&mut c);
    calibrate(&mut c);

    // A moderate push (5 Nm) accelerates the axis slowly enough for the braking-distance check
    // to see it coming: it trips before the velocity limit, and the stop ends before the limit.
    let gentle = push_towards_the_limit(&rig, &mut c, AXIS, START_DEG, 5.0, None);
    assert_eq!(gentle.check, "braking_distance", "{}", gentle.event);
    assert!(gentle.recorded < limit, "recorded {}", gentle.recorded);
    assert!(
        gentle.highest < limit,
        "{} tripped, yet axis {AXIS} reached {:.3} deg (limit {limit}) at up to {:.1} deg/s",
        gentle.check,
        gentle.highest,
        gentle.fastest
    );

    // A hard push (60 Nm): the axis overshoots the velocity limit within a cycle or two; the
    // stop after the trip must still end before the limit.
    let hard = push_towards_the_limit(&rig, &mut c, AXIS, START_DEG, 60.0, Some(&gentle.flight));
    assert!(hard.recorded < limit, "recorded {}", hard.recorded);
    assert!(
        hard.highest < limit,
        "{} tripped ({}), yet axis {AXIS} reached {:.3} deg (limit {limit}) at up to {:.1} deg/s",
        hard.check,
        hard.event["error_message"],
        hard.highest,
        hard.fastest
    );
}

// ---------------------------------------------------------------------------------------------
// 5. i2t

#[test]
fn sustained_high_current_derates_the_motor_without_an_error() {
    const AXIS: usize = 2;
    const PUSH_NM: f64 = 120.0;
    let rig = Rig::start("i2t");
    let a = &rig.cfg.axes[AXIS - 1];
    let (rated, derated_a, band) = (
        a.rated_current_a,
        a.i2t_derated_current_a,
        a.following_error_deg,
    );
    let mut c = rig.conn();
    wait_drives_online(&mut c);
    assert_status(&c.request(HOLD), "HOLD");
    let start = wait_at_rest(&mut c);
    let mut push = [0.0; 6];
    push[AXIS - 1] = PUSH_NM;
    sim(&mut c, Some(json!({"external_torques": push})));

    // Held against the push at well above the rated current until the model derates.
    let mut levels = Vec::new();
    let mut peak_current: f64 = 0.0;
    let (s, _) = wait_until(&mut c, "i2t derating", |s, t| {
        let derated = bools(&s["detail"]["i2t_derated"]);
        if derated[AXIS - 1] {
            return true;
        }
        assert_status(s, "HOLD");
        assert_eq!(derated, [false; 6], "{s}");
        assert!(
            (t.position[AXIS - 1] - start.position[AXIS - 1]).abs() < band,
            "held against the push: {t:?}"
        );
        levels.push(six(&s["detail"]["i2t"])[AXIS - 1]);
        peak_current = peak_current.max(six(&s["axis_states"]["current"])[AXIS - 1].abs());
        false
    });
    let level = six(&s["detail"]["i2t"])[AXIS - 1];
    let derated = bools(&s["detail"]["i2t_derated"]);
    eprintln!(
        "i2t: derated at level {level:.3} in mode {} after {} polls; peak current {peak_current:.2} A (rated {rated} A)",
        s["operating_mode"],
        levels.len()
    );
    assert!(level >= 1.0, "{s}");
    assert_eq!(
        derated,
        std::array::from_fn(|i| i == AXIS - 1),
        "only axis {AXIS}"
    );
    assert!(
        s["hardware_status"]
            .as_str()
            .unwrap_or_default()
            .contains("i2t derated 1"),
        "{s}"
    );
    assert!(peak_current > 2.0 * rated, "current well above rated");
    assert!(
        levels.windows(2).all(|w| w[1] >= w[0]) && levels.len() > 10,
        "the level rises: {levels:?}"
    );
    // Derating is not an error: when it was seen, no check had tripped (the overload may trip
    // a moment later, see below).
    let mode = s["operating_mode"].as_str().unwrap();
    assert!(
        mode == "HOLD" || c.events.iter().all(|e| e["check"] == "overload"),
        "{s} {:?}",
        c.events
    );

    // With the current limited to the derated current the drive can no longer hold 120 Nm:
    // the overload trips (expected) before the axis has sagged by its following-error band,
    // and the drives are powered off: the holding brakes hold the arm against the push.
    let e = c.wait_event("overload after derating", Duration::from_secs(5));
    eprintln!("i2t: after derating: {}", e["error_message"]);
    assert_event(&e, "overload", Some(AXIS as u64));
    assert!(
        e["error_message"].as_str().unwrap().contains(&format!(
            "cannot hold with its derated current of {derated_a:.2} A"
        )),
        "{e}"
    );
    let (_, braked) = wait_until(&mut c, "the drives powered off", |s, _| {
        bools(&s["detail"]["drive_enabled"]) == [false; 6]
    });
    observe(&mut c, 0.5, |s, t| {
        assert_status(s, "ERROR");
        assert!(
            (t.position[AXIS - 1] - braked.position[AXIS - 1]).abs() < 0.1,
            "held by the brake against the push: {t:?}"
        );
    });
    sim(
        &mut c,
        Some(json!({"external_torques": [0, 0, 0, 0, 0, 0]})),
    );
    assert!(
        (braked.position[AXIS - 1] - start.position[AXIS - 1]).abs() < band,
        "tripped before the following error could: {braked:?}"
    );
    wait_at_rest(&mut c);
    assert_eq!(c.events.len(), 1, "{:?}", c.events);

    // The flight recorder: the level rose through 1 while the current was far above rated;
    // at the trip the current stands at the derated limit or above it. The overload counts its
    // 25 ms (`OVERLOAD_S` in rt-core/src/controller/overload.rs) from the first report after
    // the derating, which is of the period before the drive had the limit (the current the
    // push needs), and a cycle without a new report repeats it: only where those 25 ms span
    // three cycles or more is the current at the trip surely the clamped one (200 Hz: five;
    // the emulated guest's 50 Hz: one or two).
    let f = flight(&rig, &e, "overload");
    let n = f.last();
    let i2t = f.column(&format!("i2t_{AXIS}"));
    let current = f.column(&format!("current_a_{AXIS}"));
    eprintln!(
        "i2t: recorded level {:.3} -> {:.3}, current {:.2} -> {:.2} A",
        i2t[0], i2t[n], current[0], current[n]
    );
    assert!(i2t[n] >= 1.0 && i2t[0] < i2t[n], "{} -> {}", i2t[0], i2t[n]);
    let mid = n / 2;
    assert!(
        current[mid].abs() > 2.0 * rated,
        "row {mid}: {} A",
        current[mid]
    );
    assert!(
        current[n].abs() >= 0.98 * derated_a,
        "at the derated limit {derated_a} A or above at the trip: {} A",
        current[n]
    );
    let cycles_in_overload = f64::from(rig.cfg.cycle.rate_hz) * mcm_rt_core::controller::OVERLOAD_S;
    if cycles_in_overload >= 3.0 {
        assert!(
            current[n].abs() <= derated_a * 1.05,
            "limited to {derated_a} A at the trip: {} A",
            current[n]
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 6. Power cycle

#[test]
fn a_power_cycle_loses_the_calibration_until_calibrate_runs_again() {
    let rig = Rig::start("power");
    let mut c = rig.conn();
    wait_drives_online(&mut c);
    calibrate(&mut c);
    sim(&mut c, Some(json!({"power_cycle": true})));
    let e = c.wait_event("the drives rebooting", WAIT);
    eprintln!("power cycle: {}", e["error_message"]);
    assert!(is_event(&e), "{e}");
    assert_eq!(e["check"], "drive_disconnected", "a rebooting drive: {e}");
    // The drives come back, uncalibrated: positions are raw encoder angles again.
    let (s, t) = wait_until(&mut c, "the drives back, uncalibrated", |s, _| {
        bools(&s["detail"]["drive_online"]) == [true; 6]
            && bools(&s["detail"]["calibrated"]) == [false; 6]
    });
    assert_eq!(s["detail"]["all_calibrated"], false, "{s}");
    let measured = six(&s["detail"]["measured_position"]);
    assert!(
        max_diff(&measured, &t.position) > 0.05,
        "new encoder offsets: measured {measured:?}, true {:?}",
        t.position
    );
    let (s, _) = hold_until_accepted(&mut c);
    assert_status(&s, "HOLD");
    for (mode, cmd) in MOTION_MODES {
        assert_refused(
            &c.request(cmd),
            &["refused", "axis 1 is not calibrated", "calibrate"],
        );
        assert_status(&status(&mut c), "HOLD");
        eprintln!("power cycle: {mode} refused");
    }

    calibrate(&mut c);
    let (s, t) = wait_until(&mut c, "at rest", |_, t| max_abs(&t.velocity) < 0.01);
    let measured = six(&s["detail"]["measured_position"]);
    assert!(
        max_diff(&measured, &t.position) < 0.05,
        "calibrated again: measured {measured:?}, true {:?}",
        t.position
    );
    for (mode, cmd) in MOTION_MODES {
        assert_status(&c.request(cmd), mode);
        assert_status(&c.request(HOLD), "HOLD");
    }
}

// ---------------------------------------------------------------------------------------------
// 7. Entering a motion mode uncalibrated

#[test]
fn motion_modes_are_refused_naming_the_first_uncalibrated_axis() {
    let rig = Rig::start("uncalibrated");
    let mut c = rig.conn();
    wait_drives_online(&mut c);
    assert_status(&c.request(HOLD), "HOLD");
    for (_, cmd) in MOTION_MODES {
        assert_refused(&c.request(cmd), &["refused", "axis 1 is not calibrated"]);
        assert_status(&status(&mut c), "HOLD");
    }
    // Axis 1 calibrated alone: now axis 2 is the first one missing.
    let r = c.request_within(
        r#"{"command":"calibrate","arguments":{"which":1}}"#,
        CALIBRATION_WAIT,
    );
    assert_ok(&r);
    let s = detail(&mut c);
    assert_status(&s, "HOLD");
    assert_eq!(
        bools(&s["detail"]["calibrated"]),
        [true, false, false, false, false, false],
        "{s}"
    );
    for (_, cmd) in MOTION_MODES {
        assert_refused(&c.request(cmd), &["refused", "axis 2 is not calibrated"]);
        assert_status(&status(&mut c), "HOLD");
    }
    assert!(c.events.is_empty(), "{:?}", c.events);
}
