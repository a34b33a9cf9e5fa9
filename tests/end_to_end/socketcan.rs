//! What only a kernel's CAN shows, over the virtual arm on a `vcan` interface: the frames on the
//! wire as an independent tool (`candump` of can-utils) records them, and the stop path that
//! runs only with real drives (`finish_drives` in `rt-core/src/runner.rs`).
//!
//! These tests need a kernel with SocketCAN and `vcan`, which the development and CI machines do
//! not have: they are `#[ignore]`d here and run in the test guest, where
//! `tests/vm/socketcan.rs` runs this file with `--ignored` and `MCM_TEST_BUS=socketcan` and
//! checks that every one of them passed.

use crate::common;

use common::virtual_arm::VirtualArm;
use common::{EventClient, Mcm, WAIT, assert_ok, unique_instance};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const IN_GUEST: &str = "needs a kernel with vcan: runs in the test guest (tests/vm/socketcan.rs)";

/// One frame of a candump log: its id and data bytes.
type Frame = (u16, Vec<u8>);

/// The frames of a `candump -L` log (`(time) iface id#data` lines), with their times [s].
fn read_log(path: &Path) -> Vec<(f64, Frame)> {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("read the candump log {}: {e}", path.display()));
    text.lines()
        .enumerate()
        .map(|(n, line)| {
            parse(line).unwrap_or_else(|| {
                panic!(
                    "{} line {}: not a candump -L line: {line:?}",
                    path.display(),
                    n + 1
                )
            })
        })
        .collect()
}

/// One `candump -L` line through the project's reader of that format
/// (`mcm_bus::candump::parse_line`); `None` for anything else, a blank or comment line included.
fn parse(line: &str) -> Option<(f64, Frame)> {
    let l = mcm_bus::candump::parse_line(line).ok()??;
    Some((
        l.t_us as f64 * 1e-6,
        (l.frame.id, l.frame.payload().to_vec()),
    ))
}

/// The P-Rob2 master's node id (`bus.master_node_id`).
const MASTER_NODE: u16 = 127;
/// An id no node uses: the probe that tells candump is recording.
const PROBE: u16 = 0x7FE;

/// Whether the master sends frames with this id: NMT, SYNC, RPDOs 1 and 2, SDO requests, its
/// heartbeat. Every other id is a drive's.
fn from_master(id: u16) -> bool {
    id == 0x000
        || id == 0x080
        || (0x201..=0x27F).contains(&id)
        || (0x301..=0x37F).contains(&id)
        || (0x601..=0x67F).contains(&id)
        || id == 0x700 + MASTER_NODE
}

/// `candump -L` of can-utils on `iface`, writing to a file; recording once it returns.
struct Candump {
    child: Child,
    path: PathBuf,
    iface: String,
}

impl Candump {
    fn start(iface: &str) -> Candump {
        let path = std::env::temp_dir().join(format!("{}.candump", unique_instance("kernel")));
        let file = std::fs::File::create(&path).unwrap();
        let child = Command::new("candump")
            .args(["-L", iface])
            .stdout(file)
            .stderr(Stdio::inherit())
            .spawn()
            .unwrap_or_else(|e| panic!("start candump (can-utils): {e}"));
        let dump = Candump {
            child,
            path,
            iface: iface.to_string(),
        };
        // Probe frames until one shows: candump writes a line per frame.
        let deadline = Instant::now() + WAIT;
        loop {
            let probe = format!("{PROBE:03X}#");
            let sent = Command::new("cansend")
                .args([iface, &probe])
                .status()
                .unwrap_or_else(|e| panic!("cansend (can-utils): {e}"));
            assert!(sent.success(), "cansend {iface} {probe}: {sent}");
            std::thread::sleep(Duration::from_millis(20));
            if std::fs::read_to_string(&dump.path).is_ok_and(|t| t.contains(&probe)) {
                return dump;
            }
            assert!(
                Instant::now() < deadline,
                "candump on {iface} records nothing"
            );
        }
    }

    /// Wait until `done(frames so far)` (bounded), then stop candump; its frames.
    fn stop_when(
        mut self,
        what: &str,
        done: impl Fn(&[(f64, Frame)]) -> bool,
    ) -> Vec<(f64, Frame)> {
        let deadline = Instant::now() + WAIT;
        while !done(&self.frames()) {
            assert!(
                Instant::now() < deadline,
                "candump on {}: {what} within {WAIT:?}",
                self.iface
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        // SAFETY: kill(2) with the pid of a child we own and have not reaped.
        unsafe { libc::kill(self.child.id() as i32, libc::SIGINT) };
        let _ = self.child.wait();
        self.frames()
    }

    /// The frames recorded so far (without the probes; a last line being written is skipped).
    fn frames(&self) -> Vec<(f64, Frame)> {
        let text = std::fs::read_to_string(&self.path).unwrap_or_default();
        let complete = &text[..text.rfind('\n').map_or(0, |i| i + 1)];
        complete
            .lines()
            .map(|l| parse(l).unwrap_or_else(|| panic!("candump wrote {l:?}")))
            .filter(|(_, (id, _))| *id != PROBE)
            .collect()
    }
}

/// python-can's reader of candump logs (an implementation nobody here wrote) counts the frames.
fn python_can_count(path: &Path) -> usize {
    let out = Command::new("python3")
        .args([
            "-c",
            "import can, sys; print(sum(1 for _ in can.CanutilsLogReader(sys.argv[1])))",
        ])
        .arg(path)
        .output()
        .unwrap_or_else(|e| panic!("python3: {e}"));
    assert!(
        out.status.success(),
        "python-can could not read {}: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).trim().parse().unwrap()
}

fn frames_of(log: &[(f64, Frame)], master: bool) -> Vec<Frame> {
    log.iter()
        .filter(|(_, (id, _))| from_master(*id) == master && *id != PROBE)
        .map(|(_, f)| f.clone())
        .collect()
}

/// After the last NMT "enter pre-operational" to all nodes (`000#8000`): every drive's heartbeat
/// says PRE-OPERATIONAL (0x7F).
fn all_pre_operational_after_the_stop(log: &[(f64, Frame)]) -> bool {
    let Some(stop) = log.iter().rposition(|(_, f)| *f == (0x000, vec![0x80, 0])) else {
        return false;
    };
    (1..=6u16).all(|n| {
        log[stop..]
            .iter()
            .any(|(_, (id, d))| *id == 0x700 + n && d == &[0x7F])
    })
}

/// Wait for the drives, then `hold`; a spontaneous line (a safety error) fails the test naming it.
fn online_and_hold(c: &mut common::Client) {
    let deadline = Instant::now() + WAIT;
    loop {
        let s = c.request(r#"{"command":"status","arguments":{"detail":true}}"#);
        // Under emulation the core may pause longer than the gateway's patience while it
        // starts: said so, and asked again (within the deadline). Anything else fails.
        let words = s["error_message"].as_str().unwrap_or("");
        if words.contains("is not running or not answering") {
            eprintln!("while booting: {words}");
            assert!(Instant::now() < deadline, "the core did not answer: {s}");
            std::thread::sleep(Duration::from_millis(50));
            continue;
        }
        assert_eq!(
            s["result_type"], "status",
            "a spontaneous line while booting: {s}"
        );
        if s["detail"]["drive_online"]
            .as_array()
            .is_some_and(|a| a.iter().all(|x| x == true))
        {
            break;
        }
        assert!(Instant::now() < deadline, "drives not online: {s}");
        std::thread::sleep(Duration::from_millis(50));
    }
    let s = c.request(r#"{"command":"hold"}"#);
    assert_eq!(s["operating_mode"], "HOLD", "{s}");
}

/// A virtual arm on a vcan of its own; fails outside the guest's SocketCAN mode.
fn virtual_arm() -> VirtualArm {
    assert!(
        common::virtual_arm::socketcan(),
        "{IN_GUEST}, with MCM_TEST_BUS=socketcan"
    );
    VirtualArm::start(mcm_shared::config::PROB2_DEFAULT_TOML)
}

/// An MCM over a virtual arm (launcher arguments `extra`), with candump recording the
/// interface from before the MCM's first frame.
fn recorded(tag: &str, extra: &[&str]) -> (Mcm, Candump) {
    let arm = virtual_arm();
    let dump = Candump::start(&arm.interface);
    (Mcm::start_on(Some(arm), &unique_instance(tag), extra), dump)
}

/// Stop the MCM (its controlled stop) and candump once every drive says PRE-OPERATIONAL after
/// the master's last NMT; the frames candump recorded.
fn stopped(mcm: Mcm, dump: Candump) -> Vec<(f64, Frame)> {
    let status = mcm.stop();
    assert!(status.success(), "launcher exit status {status}");
    dump.stop_when("every drive PRE-OPERATIONAL after the stop", |log| {
        all_pre_operational_after_the_stop(log)
    })
}

#[test]
#[ignore = "needs a kernel with vcan: runs in the test guest (tests/vm/socketcan.rs)"]
fn the_kernel_s_candump_agrees_with_the_mcm_s_own_log_frame_for_frame() {
    let own = std::env::temp_dir().join(format!("{}.candump", unique_instance("own")));
    let (mcm, dump) = recorded("candump", &["--candump", own.to_str().unwrap()]);
    let mut c = mcm.client();
    online_and_hold(&mut c);
    // A few seconds of cyclic traffic in HOLD.
    let s0 = common::time_of(&c.request(r#"{"command":"status","arguments":{"detail":true}}"#));
    c.wait_status("2 s of the robot's time in HOLD", |s| {
        common::time_of(s) >= s0 + 2.0
    });
    let kernel_path = dump.path.clone();
    let kernel = stopped(mcm, dump);
    let mine = read_log(&own);

    // What the master sent: the same frames in the same order.
    let (k_tx, m_tx) = (frames_of(&kernel, true), frames_of(&mine, true));
    assert!(m_tx.len() > 1000, "{} frames sent by the MCM", m_tx.len());
    if let Some(i) = (0..k_tx.len().max(m_tx.len())).find(|&i| k_tx.get(i) != m_tx.get(i)) {
        panic!(
            "the master's frame {i} differs: candump {:x?}, the MCM's log {:x?} ({} and {} frames)",
            k_tx.get(i),
            m_tx.get(i),
            k_tx.len(),
            m_tx.len()
        );
    }
    // What the drives sent: the MCM read them in the order of the wire, up to its stop (the
    // drives' heartbeats go on after it).
    let (k_rx, m_rx) = (frames_of(&kernel, false), frames_of(&mine, false));
    assert!(
        m_rx.len() > 1000,
        "{} frames received by the MCM",
        m_rx.len()
    );
    assert!(
        k_rx.len() >= m_rx.len(),
        "candump {} < MCM {}",
        k_rx.len(),
        m_rx.len()
    );
    if let Some(i) = (0..m_rx.len()).find(|&i| k_rx[i] != m_rx[i]) {
        panic!(
            "the drives' frame {i} differs: candump {:x?}, the MCM's log {:x?}",
            k_rx[i], m_rx[i]
        );
    }
    // SYNC at the configured rate, as the kernel stamped it (no bound: the guest is emulated).
    let syncs: Vec<f64> = kernel
        .iter()
        .filter(|(_, (id, _))| *id == 0x080)
        .map(|(t, _)| *t)
        .collect();
    let gaps: Vec<f64> = syncs.windows(2).map(|w| (w[1] - w[0]) * 1e6).collect();
    let mean = gaps.iter().sum::<f64>() / gaps.len() as f64;
    let worst = gaps.iter().cloned().fold(0.0, f64::max);
    eprintln!(
        "candump: {} frames, {} SYNC, period mean {mean:.1} us, longest {worst:.1} us; the MCM's log: {} frames",
        kernel.len(),
        syncs.len(),
        mine.len()
    );
    // python-can reads both logs whole.
    assert_eq!(
        python_can_count(&own),
        mine.len(),
        "python-can on the MCM's log"
    );
    // candump's log also holds the probes, which `frames` leaves out.
    let probes = std::fs::read_to_string(&kernel_path)
        .unwrap()
        .lines()
        .filter(|l| parse(l).is_some_and(|(_, (id, _))| id == PROBE))
        .count();
    assert_eq!(
        python_can_count(&kernel_path),
        kernel.len() + probes,
        "python-can on candump's log"
    );
    let _ = std::fs::remove_file(&own);
    let _ = std::fs::remove_file(&kernel_path);
}

#[test]
#[ignore = "needs a kernel with vcan: runs in the test guest (tests/vm/socketcan.rs)"]
fn after_the_controlled_stop_every_drive_is_pre_operational_and_the_master_is_silent() {
    let (mcm, dump) = recorded("finish", &[]);
    let mut c = mcm.client();
    online_and_hold(&mut c);
    let log = stopped(mcm, dump);
    // The master's last frame is the NMT to all nodes, and it sends nothing after it.
    let last = log
        .iter()
        .rev()
        .find(|(_, (id, _))| from_master(*id))
        .unwrap();
    assert_eq!(last.1, (0x000, vec![0x80, 0]), "the master's last frame");
    // Before it, every drive was disabled: its last RPDO1 no longer enables operation, and its
    // last TPDO1's statusword is not OPERATION ENABLED.
    for n in 1..=6u16 {
        let rpdo = log
            .iter()
            .rev()
            .find(|(_, (id, _))| *id == 0x200 + n)
            .unwrap();
        assert_ne!(
            rpdo.1.1.first(),
            Some(&0x0F),
            "node {n}'s last controlword {:x?}",
            rpdo.1.1
        );
        let tpdo = log
            .iter()
            .rev()
            .find(|(_, (id, _))| *id == 0x180 + n)
            .unwrap();
        let sw = u16::from_le_bytes([tpdo.1.1[0], tpdo.1.1[1]]);
        assert_ne!(
            sw & 0x6F,
            0x27,
            "node {n}'s last statusword {sw:#06x} is OPERATION ENABLED"
        );
    }
}

/// The truth of the virtual arm [deg, deg/s], through the client's routing of `sim`.
fn truth(c: &mut EventClient) -> ([f64; 6], [f64; 6]) {
    let r = c.request(r#"{"command":"sim"}"#);
    assert_eq!(r["result_type"], "sim", "{r}");
    (
        common::six(&r["true_position"]),
        common::six(&r["true_velocity"]),
    )
}

/// A detailed status; asked again while the gateway says the core does not answer (a pause of
/// the emulated core, within [`WAIT`]).
fn detail(c: &mut EventClient) -> Value {
    let deadline = Instant::now() + WAIT;
    loop {
        let s = c.request(r#"{"command":"status","arguments":{"detail":true}}"#);
        let words = s["error_message"].as_str().unwrap_or("");
        if words.contains("is not running or not answering") && Instant::now() < deadline {
            eprintln!("status: {words}");
            std::thread::sleep(Duration::from_millis(50));
            continue;
        }
        assert_eq!(s["result_type"], "status", "{s}");
        return s;
    }
}

/// Poll the truth until every axis is still (< 0.05 deg/s); the truth then.
fn at_rest(c: &mut EventClient, what: &str) -> [f64; 6] {
    arrived(c, what, None)
}

/// Poll the truth until every axis is still and, with a `target`, within 0.1 deg of it; the
/// truth then. Panics after [`WAIT`] naming the last truth.
fn arrived(c: &mut EventClient, what: &str, target: Option<&[f64; 6]>) -> [f64; 6] {
    let deadline = Instant::now() + WAIT;
    loop {
        let (p, v) = truth(c);
        if common::max_abs(&v) < 0.05 && target.is_none_or(|t| common::max_diff(&p, t) < 0.1) {
            return p;
        }
        assert!(
            Instant::now() < deadline,
            "{what}: true position {p:?}, velocity {v:?}; target {target:?}; errors {:?}",
            c.events
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Wait until all six drives are online (within [`WAIT`]); the cycle period [s] `info` gives.
fn drives_online(c: &mut EventClient) -> f64 {
    let deadline = Instant::now() + WAIT;
    while !detail(c)["detail"]["drive_online"]
        .as_array()
        .is_some_and(|a| a.iter().all(|x| x == true))
    {
        assert!(Instant::now() < deadline, "drives not online");
        std::thread::sleep(Duration::from_millis(50));
    }
    c.request(r#"{"command":"info"}"#)["cycle_time"]
        .as_f64()
        .expect("info's cycle_time")
}

#[test]
#[ignore = "needs a kernel with vcan: runs in the test guest (tests/vm/socketcan.rs)"]
fn calibration_motion_torque_control_and_an_emergency_stop_over_socketcan() {
    let mcm = Mcm::start_on(Some(virtual_arm()), &unique_instance("scenario"), &[]);
    let mut c = EventClient::connect(mcm.json);
    let cycle = drives_online(&mut c);

    // Calibration over the bus: the measured angles equal the virtual arm's true ones.
    let r = c.request_within(r#"{"command":"calibrate"}"#, Duration::from_secs(180));
    assert_ok(&r);
    let truth_now = at_rest(&mut c, "after calibration");
    let s = detail(&mut c);
    assert_eq!(s["detail"]["all_calibrated"], true, "{s}");
    let measured = common::six(&s["detail"]["measured_position"]);
    let off = common::max_diff(&measured, &truth_now);
    assert!(
        off < 0.05,
        "calibrated {measured:?} vs true {truth_now:?}: {off} deg"
    );

    // PVT at the cycle's spacing; move_all: every axis arrives on target, as the truth says.
    let r = c.request(&format!(
        r#"{{"command":"pvt","arguments":{{"dt":{cycle}}}}}"#
    ));
    assert_eq!(r["operating_mode"], "PVT", "{r}");
    let target = [10.0, -10.0, 20.0, 5.0, -5.0, 15.0];
    let r = c.request_within(&common::move_all(&target, 0.5), Duration::from_secs(60));
    assert_ne!(r["error_status"], "ERROR", "move_all: {r}");
    arrived(&mut c, "move_all", Some(&target));

    // A stream of points: axis 1 from 10 to 15 deg in 1 s, smoothstep.
    let n = (1.0 / cycle).round() as usize;
    let point = |k: usize| {
        let x = k as f64 / n as f64;
        let mut pos = target;
        let mut vel = [0.0; 6];
        pos[0] = 10.0 + 5.0 * x * x * (3.0 - 2.0 * x);
        vel[0] = 5.0 * 6.0 * x * (1.0 - x) / 1.0;
        serde_json::json!({"position": pos, "velocity": vel})
    };
    for chunk in (1..=n).collect::<Vec<_>>().chunks(10) {
        let points: Vec<Value> = chunk.iter().map(|&k| point(k)).collect();
        let r = c.request(
            &serde_json::json!({"command": "pvt_points", "arguments": {"points": points}})
                .to_string(),
        );
        assert_ok(&r);
    }
    let mut end = target;
    end[0] = 15.0;
    arrived(&mut c, "the PVT stream", Some(&end));
    let r = c.request(r#"{"command":"hold"}"#);
    assert_eq!(r["operating_mode"], "HOLD", "{r}");

    // TORQUE_CONTROL: zero torques for a while hold the arm; silence falls back to HOLD.
    let r =
        c.request(r#"{"command":"torque_control","arguments":{"timeout":0.5,"dt_status":0.1}}"#);
    assert_eq!(r["operating_mode"], "TORQUE_CONTROL", "{r}");
    for _ in 0..10 {
        let s = c
            .next(WAIT)
            .unwrap_or_else(|| panic!("no status result in TORQUE_CONTROL within {WAIT:?}"));
        if s["result_type"] == "status" && s["operating_mode"] == "HOLD" {
            panic!("fell back to HOLD while torques were sent: {s}");
        }
        c.send(r#"{"command":"set_torques","arguments":{"torques":[0,0,0,0,0,0]}}"#);
    }
    let fell_back = (0..100)
        .map(|_| c.next(WAIT).expect("a line"))
        .find(|s| s["result_type"] == "status" && s["operating_mode"] == "HOLD");
    assert!(
        fell_back.is_some(),
        "no fall-back to HOLD after the torques stopped"
    );
    let p = at_rest(&mut c, "after TORQUE_CONTROL");
    assert!(
        common::max_diff(&p, &end) < 0.5,
        "the arm moved in TORQUE_CONTROL: {p:?}"
    );

    // The emergency switch of the virtual arm: the core trips, tells the client, the arm stops.
    let r = c.request(r#"{"command":"sim","arguments":{"emergency_stop":true}}"#);
    assert_eq!(r["emergency_stop"], true, "{r}");
    let e = c.wait_event("emergency stop", WAIT);
    assert_eq!(e["check"], "emergency_stop", "{e}");
    at_rest(&mut c, "after the emergency stop");
    let r = c.request(r#"{"command":"sim","arguments":{"emergency_stop":false}}"#);
    assert_eq!(r["emergency_stop"], false, "{r}");
    let deadline = Instant::now() + WAIT;
    loop {
        let r = c.request(r#"{"command":"hold"}"#);
        if r["operating_mode"] == "HOLD" {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "hold after the emergency stop: {r}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    stop_and_check_the_drives_counters(mcm);
}

/// Stop the MCM (its controlled stop), then its virtual arm; fails when the drives counted a
/// fault ([`assert_drives_saw_no_fault`]).
fn stop_and_check_the_drives_counters(mut mcm: Mcm) {
    let arm = mcm.arm.take().expect("over the virtual arm");
    let status = mcm.stop();
    assert!(status.success(), "launcher exit status {status}");
    let counted = arm.stop();
    eprintln!("the virtual arm's counters: {}", counted.line);
    assert_drives_saw_no_fault(&counted);
}

/// No setpoint missing at a SYNC, no SDO abort, no heartbeat timeout or SYNC loss, as the drives counted,
/// and nothing lost on the wire.
fn assert_drives_saw_no_fault(c: &common::virtual_arm::ArmCounters) {
    assert!(
        c.setpoints_missing == 0
            && c.sdo_aborts == 0
            && c.heartbeat_timeouts == 0
            && c.sync_losses == 0
            && c.frames_lost_on_send == 0
            && c.wire_errors == 0,
        "the virtual arm counted faults: {}",
        c.line
    );
}

/// How long [`motion_for_minutes_with_no_pdo_lost_as_the_drives_saw_it`] runs, on the robot's
/// clock: `MCM_SOAK_S` seconds, 600 by default.
fn soak_seconds() -> f64 {
    common::env_or("MCM_SOAK_S", 600.0)
}

/// The issue's target for the guest: minutes at the configured rate with the arm moving, and
/// no lost or late setpoint, no SDO error and no heartbeat timeout as the drives saw them. Not
/// part of the CI run (10 minutes): `tests/vm/socketcan.rs`'s ignored test runs it in the guest
/// (`docs/performance.md`, "SocketCAN in the test guest").
#[test]
#[ignore = "runs for minutes in the test guest: tests/vm/socketcan.rs, docs/performance.md"]
fn motion_for_minutes_with_no_pdo_lost_as_the_drives_saw_it() {
    let seconds = soak_seconds();
    let mcm = Mcm::start_on(Some(virtual_arm()), &unique_instance("soak"), &[]);
    let mut c = EventClient::connect(mcm.json);
    let cycle = drives_online(&mut c);
    assert_ok(&c.request_within(r#"{"command":"calibrate"}"#, Duration::from_secs(180)));
    let r = c.request(&format!(
        r#"{{"command":"pvt","arguments":{{"dt":{cycle}}}}}"#
    ));
    assert_eq!(r["operating_mode"], "PVT", "{r}");

    // Back and forth between two poses, every axis moving, until `seconds` of robot time. At
    // half speed: at 0.8 the following error of axis 6 passed its 2 deg band at 50 Hz
    // (docs/performance.md, "SocketCAN in the test guest").
    let poses = [
        [30.0, -20.0, 40.0, 45.0, -30.0, 60.0],
        [-30.0, 20.0, -10.0, -45.0, 30.0, -60.0],
    ];
    let start = common::time_of(&detail(&mut c));
    let mut moves = 0;
    let mut now = start;
    while now - start < seconds {
        let target = poses[moves % 2];
        let r = c.request_within(&common::move_all(&target, 0.5), Duration::from_secs(60));
        assert_ne!(r["error_status"], "ERROR", "move_all: {r}");
        arrived(&mut c, "a move of the soak", Some(&target));
        moves += 1;
        assert!(
            c.events.is_empty(),
            "an error during the soak: {:?}",
            c.events
        );
        now = common::time_of(&detail(&mut c));
    }

    let s = detail(&mut c);
    assert_eq!(s["operating_mode"], "PVT", "{s}");
    let timing = &s["detail"]["timing"];
    let bus = &s["detail"]["bus"];
    eprintln!(
        "soak: {:.0} s of robot time at {:.0} Hz, {moves} moves; core: {} cycles, wake-up latency \
         p50 {} us, p99 {} us, p99.9 {} us, max {} us, work max {} us (budget {} us), {} \
         overruns, {} over budget; bus: {bus}",
        now - start,
        1.0 / cycle,
        timing["cycles"],
        timing["latency_p50_us"],
        timing["latency_p99_us"],
        timing["latency_p99_9_us"],
        timing["latency_max_us"],
        timing["work_max_us"],
        timing["work_budget_us"],
        timing["overruns"],
        timing["over_budget"],
    );
    for key in [
        "bad_frames",
        "bus_errors",
        "frames_dropped",
        "events_dropped",
    ] {
        assert_eq!(bus[key], 0, "detail.bus.{key}: {bus}");
    }
    stop_and_check_the_drives_counters(mcm);
}
