//! The end-to-end tests over a kernel's SocketCAN (`MCM_TEST_BUS=socketcan`, set inside the
//! test guest, docs/testing.md): every [`crate::common::Mcm`] then gets a CAN interface
//! of its own (a new `vcan`), a virtual arm on it (`mcm virtual-arm`), and a core with
//! `bus.backend = "socketcan"` on that interface instead of the in-process simulated bus. The
//! tests stay as they are: the clients ([`crate::common::Client`],
//! [`crate::common::EventClient`]) send every `sim` request (fault injection, ground truth) to
//! the virtual arm's control socket, which answers it as the gateway does on the simulated
//! robot, and everything else to the gateway.

use mcm_shared::ready::VirtualArmReady;
use serde_json::Value;
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::net::{SocketAddr, TcpStream};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex, mpsc};
use std::time::Duration;

/// The `mcm` binary the tests start: `MCM_TEST_BINARY` when set (the test guest runs the
/// release build: a debug build under software emulation cannot keep the 200 Hz cycle), else
/// the one cargo built with the tests.
pub fn mcm_binary() -> std::path::PathBuf {
    std::env::var_os("MCM_TEST_BINARY")
        .map(Into::into)
        .unwrap_or_else(|| env!("CARGO_BIN_EXE_mcm").into())
}

/// Whether the MCMs of this test process run over SocketCAN.
pub fn socketcan() -> bool {
    std::env::var("MCM_TEST_BUS").is_ok_and(|v| v == "socketcan")
}

/// Gateway JSON port -> the control address of the virtual arm behind it (by port: a client
/// may reach the gateway on another of the host's addresses than the one it printed).
static ARMS: Mutex<Option<HashMap<u16, SocketAddr>>> = Mutex::new(None);
static INTERFACES: AtomicU32 = AtomicU32::new(0);

/// The virtual arm behind the gateway at `json`, if that MCM runs over SocketCAN.
pub fn arm_behind(json: SocketAddr) -> Option<SocketAddr> {
    let arms = ARMS.lock().unwrap_or_else(|e| e.into_inner());
    arms.as_ref()?.get(&json.port()).copied()
}

/// Whether `json` (one request line) is a `sim` command.
pub fn is_sim(json: &str) -> bool {
    serde_json::from_str::<Value>(json).is_ok_and(|v| v["command"] == "sim")
}

/// Ask the virtual arm at `control` one request line; its answer.
pub fn ask(control: SocketAddr, json: &str) -> Value {
    let mut s = TcpStream::connect(control)
        .unwrap_or_else(|e| panic!("connect to the virtual arm at {control}: {e}"));
    s.set_read_timeout(Some(super::WAIT)).unwrap();
    writeln!(s, "{json}").unwrap();
    let mut line = String::new();
    BufReader::new(s)
        .read_line(&mut line)
        .unwrap_or_else(|e| panic!("the virtual arm's answer to {json}: {e}"));
    serde_json::from_str(&line).unwrap_or_else(|e| panic!("{e}: {line:?}"))
}

fn ip(args: &[&str]) {
    let out = Command::new("ip")
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("ip {}: {e}", args.join(" ")));
    assert!(
        out.status.success(),
        "ip {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A virtual arm on a `vcan` interface of its own; dropping it stops the arm and removes the
/// interface.
pub struct VirtualArm {
    child: Child,
    pub interface: String,
    pub control: SocketAddr,
    /// The configuration file the arm and the core read (`bus.backend = "socketcan"`).
    pub config: super::TempConfig,
    /// The last counters line the arm printed on stderr (`mcm-virtual-arm: arm time ...`).
    counters: Arc<Mutex<Option<String>>>,
}

/// What the virtual arm counted, from its last counters line (`docs/virtual-arm.md`).
#[derive(Debug, Clone, PartialEq)]
pub struct ArmCounters {
    /// The whole line, as printed.
    pub line: String,
    pub arm_time_s: f64,
    pub syncs: u64,
    pub periods_without_sync: u64,
    pub frames_lost_on_send: u64,
    pub wire_errors: u64,
    /// As the drives saw it: a SYNC with no new setpoint (RPDO1) since the last one.
    pub setpoints_missing: u64,
    pub sdo_aborts: u64,
    pub heartbeat_timeouts: u64,
    /// Drives faulted for want of SYNC while enabled.
    pub sync_losses: u64,
}

impl ArmCounters {
    /// Parse a counters line; `None` when it is not one.
    pub fn parse(line: &str) -> Option<ArmCounters> {
        let rest = line.strip_prefix("mcm-virtual-arm: arm time ")?;
        let after = |key: &str| -> Option<&str> {
            let at = rest.find(key)? + key.len();
            Some(rest[at..].trim_start())
        };
        let number = |key: &str| -> Option<u64> {
            let v = after(key)?;
            let end = v.find(|c: char| !c.is_ascii_digit()).unwrap_or(v.len());
            v[..end].parse().ok()
        };
        let time = rest.split_whitespace().next()?.parse().ok()?;
        Some(ArmCounters {
            line: line.to_owned(),
            arm_time_s: time,
            syncs: number("; SYNC ")?,
            periods_without_sync: number("periods without SYNC ")?,
            frames_lost_on_send: number("frames lost on send ")?,
            wire_errors: number("wire errors ")?,
            setpoints_missing: number("setpoints missing at SYNC ")?,
            sdo_aborts: number("SDO aborts ")?,
            heartbeat_timeouts: number("heartbeat timeouts ")?,
            sync_losses: number("SYNC losses ")?,
        })
    }
}

impl VirtualArm {
    /// A new `vcan` interface and a virtual arm on it, configured as `config_text` (a robot
    /// configuration) says, over which the core will run.
    pub fn start(config_text: &str) -> VirtualArm {
        let interface = format!(
            "mv{}x{}",
            std::process::id() % 100_000,
            INTERFACES.fetch_add(1, Ordering::Relaxed)
        );
        ip(&["link", "add", "dev", &interface, "type", "vcan"]);
        ip(&["link", "set", "up", &interface]);
        let text = over_socketcan(config_text, &interface);
        let config = super::config_file("vcan", |_| text);
        let mut child = Command::new(mcm_binary())
            .args(["virtual-arm", "--interface", &interface])
            .args(["--control", "127.0.0.1:0", "--summary-s", "0"])
            // Below the core's cycle (priority 80): the guest is emulated and shared.
            .args(["--fifo-priority", "70"])
            .args(["--config", config.path()])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("start mcm virtual-arm: {e}"));
        // Its stderr passed on as it comes, the last counters line kept.
        let counters = Arc::new(Mutex::new(None));
        let stderr = child.stderr.take().unwrap();
        let last = Arc::clone(&counters);
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines() {
                let Ok(line) = line else { break };
                eprintln!("{line}");
                if line.starts_with("mcm-virtual-arm: arm time ") {
                    *last.lock().unwrap_or_else(|e| e.into_inner()) = Some(line);
                }
            }
        });
        let stdout = child.stdout.take().unwrap();
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if let Ok(r) = line.parse::<VirtualArmReady>() {
                    let _ = tx.send(r);
                }
            }
        });
        let ready = rx.recv_timeout(super::WAIT).unwrap_or_else(|_| {
            let _ = child.kill();
            panic!(
                "mcm virtual-arm on {interface}: no ready line within {:?}",
                super::WAIT
            )
        });
        VirtualArm {
            child,
            interface,
            control: ready.control,
            config,
            counters,
        }
    }

    /// Route the `sim` requests of clients of the gateway at `json` to this arm.
    pub fn serve_clients_of(&self, json: SocketAddr) {
        let mut arms = ARMS.lock().unwrap_or_else(|e| e.into_inner());
        arms.get_or_insert_with(HashMap::new)
            .insert(json.port(), self.control);
    }
}

/// The cycle rate and bus timing of an emulated machine (`MCM_TEST_EMULATED=1`, which the test
/// guest sets): software emulation on a 2-core host wakes the core up to 10 ms late (p99,
/// measured; docs/virtual-arm.md), which the P-Rob2's 200 Hz with a 150 ms heartbeat timeout and 3
/// missed TPDOs cannot absorb. `(section, key, value)`.
pub const EMULATED: &[(&str, &str, &str)] = &[
    ("cycle", "rate_hz", "50"),
    ("cycle", "work_budget_us", "10000"),
    ("bus", "master_heartbeat_ms", "100"),
    ("bus", "drive_heartbeat_ms", "100"),
    ("bus", "heartbeat_timeout_ms", "1000"),
    ("bus", "sdo_timeout_ms", "200"),
    ("bus", "max_missed_tpdos", "10"),
];

/// Whether this test process runs on an emulated machine (the test guest).
pub fn emulated() -> bool {
    std::env::var("MCM_TEST_EMULATED").is_ok_and(|v| v == "1")
}

/// `text` (a robot configuration) with the bus on SocketCAN interface `interface` (and, on an
/// emulated machine, its timing: [`EMULATED`]).
pub fn over_socketcan(text: &str, interface: &str) -> String {
    let iface = format!("\"{interface}\"");
    let mut edits = vec![
        ("bus", "backend", "\"socketcan\""),
        ("bus", "interface", iface.as_str()),
    ];
    if emulated() {
        edits.extend_from_slice(EMULATED);
    }
    let mut out = String::new();
    let mut section = "";
    let mut done = vec![false; edits.len()];
    for line in text.lines() {
        let trimmed = line.trim();
        if trimmed.starts_with('[') {
            section = trimmed.trim_matches(|c| c == '[' || c == ']');
        }
        let key = line.split('=').next().unwrap_or("").trim();
        match edits
            .iter()
            .position(|(s, k, _)| *s == section && *k == key)
        {
            Some(i) if !trimmed.starts_with('#') => {
                out.push_str(&format!("{key} = {}\n", edits[i].2));
                done[i] = true;
            }
            _ => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    for (i, (s, k, _)) in edits.iter().enumerate() {
        assert!(done[i], "no {s}.{k} in the configuration");
    }
    out
}

impl VirtualArm {
    /// Stop the arm (SIGTERM; SIGKILL after 5 s) and wait for it to end.
    fn end(&mut self) {
        if self.child.try_wait().ok().flatten().is_some() {
            return;
        }
        // SAFETY: kill(2) with a pid of a child we own and have not reaped.
        unsafe { libc::kill(self.child.id() as i32, libc::SIGTERM) };
        let deadline = std::time::Instant::now() + Duration::from_secs(5);
        while self.child.try_wait().ok().flatten().is_none() {
            if std::time::Instant::now() > deadline {
                let _ = self.child.kill();
                break;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = self.child.wait();
    }

    /// Stop the arm; what it counted, from the counters line it prints when it ends. Panics
    /// when it printed none within [`super::WAIT`].
    pub fn stop(mut self) -> ArmCounters {
        self.end();
        let deadline = std::time::Instant::now() + super::WAIT;
        loop {
            let last = self
                .counters
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .clone();
            // The line printed at the end is the last one (the reader thread ends with it).
            if let Some(line) = last
                && (Arc::strong_count(&self.counters) == 1 || std::time::Instant::now() > deadline)
            {
                return ArmCounters::parse(&line)
                    .unwrap_or_else(|| panic!("not a counters line: {line:?}"));
            }
            assert!(
                std::time::Instant::now() < deadline,
                "the virtual arm on {} printed no counters",
                self.interface
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for VirtualArm {
    fn drop(&mut self) {
        self.end();
        let _ = Command::new("ip")
            .args(["link", "del", "dev", &self.interface])
            .status();
    }
}
