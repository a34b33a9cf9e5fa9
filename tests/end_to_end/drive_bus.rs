//! End to end: the drive bus through the real launcher. HOLD keeps the simulated arm still (in
//! a pose loaded by gravity), a drive that goes silent is seen within the heartbeat timeout and
//! reported to the client, the candump log is well formed and shows the CANopen traffic, and a
//! configuration selecting a SocketCAN interface that cannot be opened makes the launcher stop
//! with a message naming it.

use crate::common;

use common::flight::Flight;
use common::{Client, Mcm, WAIT, unique_instance};
use serde_json::Value;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const HOLD: &str = r#"{"command":"hold"}"#;
const STATUS: &str = r#"{"command":"status","arguments":{"detail":true}}"#;
const SIM: &str = r#"{"command":"sim"}"#;

/// `bus.heartbeat_timeout_ms` of deploy/prob2.toml [s].
const HEARTBEAT_TIMEOUT_S: f64 = 0.150;
/// The cycle period of deploy/prob2.toml [s].
const PERIOD_S: f64 = 0.005;

fn six(v: &Value) -> [f64; 6] {
    let a = v
        .as_array()
        .unwrap_or_else(|| panic!("expected an array of six numbers, got {v}"));
    assert_eq!(a.len(), 6, "six values: {v}");
    core::array::from_fn(|i| a[i].as_f64().unwrap())
}

/// A spontaneous result (a safety error sent to every client) carries `check`.
fn spontaneous(v: &Value) -> bool {
    v.get("check").is_some()
}

/// Send one command and read its result, skipping spontaneous safety errors.
fn reply(c: &mut Client, json: &str) -> Value {
    if c.virtual_arm().is_some() && common::virtual_arm::is_sim(json) {
        return c.request(json); // over SocketCAN the virtual arm answers it
    }
    c.send_raw(format!("{json}\n").as_bytes());
    c.recv_matching(|v| !spontaneous(v))
}

/// One look at the arm: the robot's time (of the newest state) and, right after it, the true
/// joint angles.
fn look(c: &mut Client) -> (f64, [f64; 6]) {
    let s = reply(c, STATUS);
    assert_eq!(s["result_type"], "status", "{s}");
    (six(&s["axis_states"]["time"])[0], true_position(c))
}

fn true_position(c: &mut Client) -> [f64; 6] {
    let r = reply(c, SIM);
    assert_eq!(r["result_type"], "sim", "{r}");
    six(&r["true_position"])
}

/// A copy of deploy/prob2.toml in the temp directory with the lines starting with each
/// `key = ` replaced by `key = value` (each key must occur exactly once). Removed on drop.
struct TempConfig(std::path::PathBuf);

impl TempConfig {
    fn new(tag: &str, changes: &[(&str, &str)]) -> TempConfig {
        // As embedded (the test guest has the binaries, not the sources).
        let toml = mcm_shared::config::PROB2_DEFAULT_TOML;
        let mut found = vec![0; changes.len()];
        let toml: String = toml
            .lines()
            .map(|l| {
                for (i, (key, value)) in changes.iter().enumerate() {
                    if l.starts_with(&format!("{key} = ")) {
                        found[i] += 1;
                        return format!("{key} = {value}\n");
                    }
                }
                format!("{l}\n")
            })
            .collect();
        for ((key, _), n) in changes.iter().zip(found) {
            assert_eq!(n, 1, "`{key} = ` occurs once in deploy/prob2.toml");
        }
        let path = std::env::temp_dir().join(format!("mcm-{}.toml", unique_instance(tag)));
        std::fs::write(&path, toml).unwrap();
        TempConfig(path)
    }

    fn path(&self) -> &str {
        self.0.to_str().unwrap()
    }
}

impl Drop for TempConfig {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

fn hold(c: &mut Client) {
    c.wait_drives_online();
    let s = reply(c, HOLD);
    assert_eq!(s["result_type"], "status", "{s}");
    assert_eq!(s["operating_mode"], "HOLD", "{s}");
}

#[test]
fn hold_keeps_the_arm_still() {
    const OBSERVE_S: f64 = 3.0;
    const MIN_LOOKS: usize = 15;
    const BAND_DEG: f64 = 0.05;
    /// How far enabling the drives under gravity may move the arm: a quarter of the
    /// following-error band (`following_error_deg` = 2). In this pose it is 0.22 deg on axis 2
    /// (the position loops take the load only once the brakes are open).
    const ENABLE_BUMP_DEG: f64 = 0.5;
    // A pose where gravity loads the shoulder, elbow and wrist.
    let cfg = TempConfig::new(
        "still",
        &[("initial_position_deg", "[10.0, 45.0, 30.0, 0.0, 30.0, 0.0]")],
    );
    let mcm = Mcm::start_with("still", &["--config", cfg.path()]);
    let mut c = mcm.client();
    c.wait_drives_online();
    let braked = true_position(&mut c);
    let s = reply(&mut c, HOLD);
    assert_eq!(s["operating_mode"], "HOLD", "{s}");

    // Enabling under gravity: the brakes open and the position loops take the load, which
    // moves the arm a little until they have settled. Follow that as closely as the round
    // trips allow, until the arm has been still (within 0.001 deg) for half a second of the
    // robot's clock.
    const STILL_FOR_S: f64 = 0.5;
    let mut bump = [0.0f64; 6];
    let mut recent: Vec<(f64, [f64; 6])> = Vec::new();
    let deadline = Instant::now() + WAIT;
    loop {
        let (t, p) = look(&mut c);
        for i in 0..6 {
            bump[i] = bump[i].max((p[i] - braked[i]).abs());
        }
        recent.push((t, p));
        let moved_since = recent
            .iter()
            .rev()
            .find(|(_, q)| (0..6).any(|i| (q[i] - p[i]).abs() >= 0.001))
            .map_or(recent[0].0, |(t, _)| *t);
        if t - moved_since >= STILL_FOR_S {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "the arm did not settle within {WAIT:?} after hold: {p:?}"
        );
        // Pacing: one look per ~20 ms.
        std::thread::sleep(Duration::from_millis(20));
    }
    eprintln!(
        "HOLD: enabling moved the arm by up to {bump:.4?} deg; still after {} looks",
        recent.len()
    );
    for (i, b) in bump.iter().enumerate() {
        assert!(
            *b < ENABLE_BUMP_DEG,
            "enabling moved axis {} by {b:.4} deg; allowed {ENABLE_BUMP_DEG}",
            i + 1
        );
    }

    // Watch for OBSERVE_S of the robot's clock, at least MIN_LOOKS looks (one every ~100 ms).
    let (t0, first) = look(&mut c);
    let (mut min, mut max) = (first, first);
    let mut samples = 1;
    let deadline = Instant::now() + WAIT;
    let mut t = t0;
    while t - t0 < OBSERVE_S || samples < MIN_LOOKS {
        assert!(
            Instant::now() < deadline,
            "{samples} looks over {:.3} s of robot time within {WAIT:?}",
            t - t0
        );
        // Pacing of the observation, not a synchronisation.
        std::thread::sleep(Duration::from_millis(100));
        let p;
        (t, p) = look(&mut c);
        for i in 0..6 {
            min[i] = min[i].min(p[i]);
            max[i] = max[i].max(p[i]);
        }
        samples += 1;
    }
    let last = true_position(&mut c);
    let spread: [f64; 6] = core::array::from_fn(|i| max[i] - min[i]);
    eprintln!(
        "HOLD: {samples} looks in {:.3} s of robot time, spread per axis [deg] {spread:.6?}",
        t - t0
    );
    for i in 0..6 {
        let spread = max[i] - min[i];
        assert!(
            spread < BAND_DEG,
            "axis {} moved {spread:.4} deg while holding (min {:.4}, max {:.4}); allowed {BAND_DEG}",
            i + 1,
            min[i],
            max[i]
        );
        let drift = (last[i] - first[i]).abs();
        assert!(
            drift < BAND_DEG,
            "axis {} is {drift:.4} deg away from where it was {OBSERVE_S} s ago",
            i + 1
        );
        let drift = (last[i] - braked[i]).abs();
        assert!(
            drift < BAND_DEG,
            "axis {} holds {drift:.4} deg away from where the brakes held it",
            i + 1
        );
    }
    let s = reply(&mut c, STATUS);
    assert_eq!(s["operating_mode"], "HOLD", "still holding: {s}");

    // The observation can see motion: a hand pushing on axis 1 moves it measurably (the
    // position controller pulls it back, but not without a deflection).
    let r = reply(
        &mut c,
        r#"{"command":"sim","arguments":{"external_torques":[20,0,0,0,0,0]}}"#,
    );
    assert_eq!(r["result_type"], "sim", "{r}");
    let deadline = Instant::now() + WAIT;
    loop {
        let p = true_position(&mut c);
        if (p[0] - last[0]).abs() > 0.001 {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "a 20 Nm push did not move axis 1 within {WAIT:?}: {p:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn a_silent_drive_is_detected_within_the_heartbeat_timeout_and_hold_recovers() {
    let mcm = Mcm::start("disconnect");
    let mut c = mcm.client();
    hold(&mut c);
    let before = reply(&mut c, STATUS);
    assert_eq!(before["operating_mode"], "HOLD", "{before}");

    c.send_raw(b"{\"command\":\"sim\",\"arguments\":{\"disconnect_axis\":3}}\n");
    // The sim result and the spontaneous error, in whichever order they come.
    let (mut sim, mut error) = (None, None);
    while sim.is_none() || error.is_none() {
        let v = c.recv();
        if spontaneous(&v) {
            assert!(error.is_none(), "one spontaneous error, got another: {v}");
            error = Some(v);
        } else {
            assert!(sim.is_none(), "one sim result, got another: {v}");
            sim = Some(v);
        }
    }
    let (sim, error) = (sim.unwrap(), error.unwrap());
    assert_eq!(sim["result_type"], "sim", "{sim}");
    common::assert_error(&error, &["axis 3"]);
    assert_eq!(error["check"], "drive_disconnected", "{error}");
    assert_eq!(error["axis"], 3, "{error}");

    let after = reply(&mut c, STATUS);
    assert_eq!(after["operating_mode"], "ERROR", "{after}");
    assert_eq!(after["detail"]["drive_online"][2], false, "{after}");
    // The detection delay on the robot's clock, from the flight-recorder file the error names:
    // from the cycle that served the `sim` (the drive went silent) to the trip.
    let file = std::path::PathBuf::from(
        error["flight_recorder"]
            .as_str()
            .unwrap_or_else(|| panic!("no flight_recorder in {error}")),
    );
    let f = Flight::read(&file);
    let _ = std::fs::remove_file(&file);
    let (silent, trip) = (f.last_sim_before_trip(), f.last());
    let delay = f.num(trip, "t_s") - f.num(silent, "t_s");
    eprintln!(
        "silent drive reported {:.1} ms ({} cycles) after it went silent",
        delay * 1e3,
        f.num(trip, "cycle") - f.num(silent, "cycle")
    );
    let allowed = HEARTBEAT_TIMEOUT_S + 4.0 * PERIOD_S;
    assert!(
        delay > 0.0 && delay < allowed,
        "the silent drive was reported {:.1} ms after it went silent; allowed {:.1} ms",
        delay * 1e3,
        allowed * 1e3
    );

    let r = reply(
        &mut c,
        r#"{"command":"sim","arguments":{"reconnect_axis":3}}"#,
    );
    assert_eq!(r["result_type"], "sim", "{r}");
    // The drive answers again after a heartbeat or two (or a reboot): `hold` is refused until
    // the master has it back, then accepted.
    let deadline = Instant::now() + WAIT;
    let s = loop {
        let s = reply(&mut c, HOLD);
        if s["result_type"] == "status" {
            break s;
        }
        common::assert_error(&s, &["hold"]);
        assert!(
            Instant::now() < deadline,
            "hold still refused {WAIT:?} after reconnecting axis 3: {s}"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    assert_eq!(s["operating_mode"], "HOLD", "{s}");
    let d = reply(&mut c, STATUS);
    assert_eq!(
        six_bools(&d["detail"]["drive_enabled"]),
        [true; 6],
        "every drive enabled again: {d}"
    );
}

fn six_bools(v: &Value) -> [bool; 6] {
    let a = v.as_array().unwrap_or_else(|| panic!("six booleans: {v}"));
    assert_eq!(a.len(), 6, "{v}");
    core::array::from_fn(|i| a[i].as_bool().unwrap())
}

/// One candump frame line: `(<secs>.<6 digits>) <iface> <3 hex>#<even number of hex digits>`.
/// Returns the identifier and the payload's hex digits.
fn parse_candump(line: &str) -> Option<(u16, String)> {
    let hex = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_hexdigit());
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let mut words = line.split(' ');
    let (stamp, iface, frame) = (words.next()?, words.next()?, words.next()?);
    if words.next().is_some() || iface != "sim0" {
        return None;
    }
    let (secs, micros) = stamp
        .strip_prefix('(')?
        .strip_suffix(')')?
        .split_once('.')?;
    if !digits(secs) || !digits(micros) || micros.len() != 6 {
        return None;
    }
    let (id, data) = frame.split_once('#')?;
    if id.len() != 3 || !hex(id) || data.len() % 2 != 0 || !(data.is_empty() || hex(data)) {
        return None;
    }
    Some((u16::from_str_radix(id, 16).ok()?, data.to_string()))
}

#[test]
fn the_candump_parser_refuses_malformed_lines() {
    assert_eq!(
        parse_candump("(1735270496.916858) sim0 185#3702A0860100"),
        Some((0x185, "3702A0860100".into()))
    );
    assert_eq!(
        parse_candump("(1735270496.916858) sim0 080#"),
        Some((0x80, String::new()))
    );
    for bad in [
        "(1735270496.91685) sim0 080#",
        "1735270496.916858 sim0 080#",
        "(1735270496.916858) can0 080#",
        "(1735270496.916858) sim0 80#",
        "(1735270496.916858) sim0 080#1",
        "(1735270496.916858) sim0 080#0G",
        "(1735270496.916858) sim0 080# T",
    ] {
        assert_eq!(parse_candump(bad), None, "{bad:?}");
    }
}

#[test]
fn the_candump_log_shows_the_canopen_traffic() {
    let path = std::env::temp_dir().join(format!("mcm-{}.candump", unique_instance("candump")));
    let mcm = Mcm::start_with("candump", &["--candump", path.to_str().unwrap()]);
    let mut c = mcm.client();
    hold(&mut c);
    let status = mcm.stop();
    assert!(status.success(), "launcher exit status {status}");

    let log = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("read the candump log {}: {e}", path.display()));
    let mut ids = std::collections::BTreeMap::<u16, usize>::new();
    let mut last_data = std::collections::BTreeMap::<u16, String>::new();
    // Every line is a candump frame line: no comment lines, which candump's readers refuse.
    for (n, line) in log.lines().enumerate() {
        let (id, data) = parse_candump(line)
            .unwrap_or_else(|| panic!("line {} of the candump log is malformed: {line:?}", n + 1));
        *ids.entry(id).or_default() += 1;
        last_data.insert(id, data);
    }
    let count = |id: u16| ids.get(&id).copied().unwrap_or(0);
    assert!(count(0x080) > 0, "SYNC frames 080#: {ids:x?}");
    for node in 1..=6u16 {
        assert!(count(0x200 + node) > 0, "RPDO1 of node {node}: {ids:x?}");
        assert!(count(0x180 + node) > 0, "TPDO1 of node {node}: {ids:x?}");
        assert!(
            count(0x600 + node) > 0,
            "SDO configuration of node {node}: {ids:x?}"
        );
    }
    // Written to the end, through the controlled stop: each drive's last RPDO1 no longer
    // enables operation (controlword 0x000F, little-endian first).
    assert!(log.ends_with('\n'), "the last line is complete");
    for node in 1..=6u16 {
        let cw = &last_data[&(0x200 + node)];
        assert!(
            !cw.to_ascii_uppercase().starts_with("0F00"),
            "node {node}'s last RPDO1 {cw} still enables operation: the log ends before the stop"
        );
    }
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn a_socketcan_interface_that_cannot_be_opened_stops_the_launcher_with_its_name() {
    const IFACE: &str = "mcmtest0";
    let cfg = TempConfig::new(
        "socketcan",
        &[
            ("backend", "\"socketcan\""),
            ("interface", &format!("\"{IFACE}\"")),
        ],
    );
    let instance = unique_instance("socketcan");
    let mut child = Command::new(env!("CARGO_BIN_EXE_mcm"))
        .args(["--config", cfg.path(), "--instance", &instance])
        .args([
            "--bind",
            "127.0.0.1",
            "--json-port",
            "0",
            "--hmi-port",
            "0",
            "--http-port",
            "0",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start mcm");
    let deadline = Instant::now() + WAIT;
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("mcm with an unusable CAN interface still runs after {WAIT:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success(),
        "exit status {}; stderr: {stderr}",
        out.status
    );
    assert!(
        stderr.contains(IFACE),
        "stderr names the interface: {stderr}"
    );
    assert!(
        stderr.contains("no SocketCAN support") || stderr.contains("no such network interface"),
        "stderr says why the interface cannot be opened: {stderr}"
    );
    assert!(
        !String::from_utf8_lossy(&out.stdout).contains("MCM ready"),
        "never said it was ready"
    );
}
