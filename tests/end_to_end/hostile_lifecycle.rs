//! End to end, the MCM's life under an operator's (and an accident's) hand: SIGTERM while the
//! arm moves brings it to standstill (measured against the simulation's true velocity) and
//! disables the drives before anything exits, and every client is told; `kill -9` of the
//! launcher does not orphan its children; `kill -9` of `mcm-rt` reaches clients as the core
//! vanishing, before the launcher stops the gateway; a gateway that keeps dying is restarted
//! with a back-off while `mcm-rt` keeps the arm; the gateway stopped and continued 20 times
//! keeps serving; a configuration that switches a safety check off is refused at start, naming
//! the key.
//!
//! Real processes (the `mcm` launcher, `mcm-rt`, `mcm-gateway`), unique instance names and
//! free ports; every wait is bounded.

use crate::common;

use common::{WAIT, alive, config_file, unique_instance};
use mcm_shared::ready::{McmReady, ReadyLine};
use mcm_shared::restart::GATEWAY_RESTART;
use mcm_shared::service::sim_state_path;
use serde_json::{Value, json};
use std::io::{BufRead, BufReader, Write};
use std::net::{SocketAddr, TcpStream};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex, mpsc};
use std::time::{Duration, Instant};

/// The launcher with both of its output streams captured (the log is on stderr).
struct Launcher {
    child: Child,
    stdout: mpsc::Receiver<String>,
    log: Arc<Mutex<Vec<String>>>,
    instance: String,
    json: SocketAddr,
    hmi: SocketAddr,
    rt_pid: i32,
    gateway_pid: i32,
}

fn spawn(
    instance: &str,
    extra: &[&str],
) -> (Child, mpsc::Receiver<String>, Arc<Mutex<Vec<String>>>) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_mcm"))
        .args(["--instance", instance, "--bind", "127.0.0.1"])
        .args(["--json-port", "0", "--hmi-port", "0", "--http-port", "0"])
        .args(extra)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start mcm");
    let (tx, rx) = mpsc::channel();
    let stdout = child.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            eprintln!("[mcm] {line}");
            let _ = tx.send(line);
        }
    });
    let log = Arc::new(Mutex::new(Vec::new()));
    let stderr = child.stderr.take().unwrap();
    let sink = log.clone();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            eprintln!("[mcm stderr] {line}");
            sink.lock().unwrap().push(line);
        }
    });
    (child, rx, log)
}

impl Launcher {
    fn start(tag: &str) -> Launcher {
        let instance = unique_instance(tag);
        let (child, stdout, log) = spawn(&instance, &[]);
        let mut l = Launcher {
            child,
            stdout,
            log,
            instance,
            json: "127.0.0.1:0".parse().unwrap(),
            hmi: "127.0.0.1:0".parse().unwrap(),
            rt_pid: 0,
            gateway_pid: 0,
        };
        l.wait_ready();
        l
    }

    /// The next "MCM ready" line: addresses and pids.
    fn wait_ready(&mut self) {
        let deadline = Instant::now() + WAIT;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let line = self
                .stdout
                .recv_timeout(left)
                .unwrap_or_else(|e| panic!("no `MCM ready` within {WAIT:?}: {e}"));
            if line.starts_with(McmReady::PREFIX) {
                let ready: McmReady = line.parse().unwrap_or_else(|e| panic!("{e}"));
                assert_eq!(ready.instance, self.instance);
                self.json = ready.gateway.json;
                self.hmi = ready.gateway.hmi;
                self.rt_pid = ready.rt_pid as i32;
                self.gateway_pid = ready.gateway_pid as i32;
                return;
            }
        }
    }

    fn signal(&self, sig: i32) {
        // SAFETY: signalling our own child.
        unsafe { libc::kill(self.child.id() as i32, sig) };
    }

    /// Wait (bounded) for the launcher to exit.
    fn wait_exit(&mut self) -> std::process::ExitStatus {
        let deadline = Instant::now() + WAIT;
        loop {
            if let Some(s) = self.child.try_wait().unwrap() {
                return s;
            }
            assert!(
                Instant::now() < deadline,
                "mcm did not exit within {WAIT:?}"
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Wait (bounded) for a log line containing `words`; the line.
    fn wait_log(&self, words: &str) -> String {
        let deadline = Instant::now() + WAIT;
        loop {
            if let Some(l) = self.log.lock().unwrap().iter().find(|l| l.contains(words)) {
                return l.clone();
            }
            assert!(
                Instant::now() < deadline,
                "no log line with {words:?} within {WAIT:?}; log: {:#?}",
                self.log.lock().unwrap()
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for Launcher {
    fn drop(&mut self) {
        if self.child.try_wait().ok().flatten().is_none() {
            self.signal(libc::SIGTERM);
            let deadline = Instant::now() + WAIT;
            while self.child.try_wait().ok().flatten().is_none() && Instant::now() < deadline {
                std::thread::sleep(Duration::from_millis(10));
            }
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
        for pid in [self.rt_pid, self.gateway_pid] {
            if pid > 0 && !gone(pid) {
                // SAFETY: a process this test started (through the launcher).
                unsafe { libc::kill(pid, libc::SIGKILL) };
            }
        }
        let _ = std::fs::remove_file(sim_state_path(&self.instance));
    }
}

/// The process no longer runs (gone, or a zombie nobody reaped yet).
fn gone(pid: i32) -> bool {
    if !alive(pid) {
        return true;
    }
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .map(|s| {
            s.rsplit(')')
                .next()
                .unwrap_or("")
                .trim_start()
                .starts_with('Z')
        })
        .unwrap_or(true)
}

fn wait_gone(pid: i32, what: &str) {
    let deadline = Instant::now() + WAIT;
    while !gone(pid) {
        assert!(
            Instant::now() < deadline,
            "{what} (pid {pid}) still runs after {WAIT:?}"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// A JSON connection that survives the server closing it.
struct Conn {
    stream: TcpStream,
    reader: BufReader<TcpStream>,
    /// Every spontaneous ERROR notice seen, in order.
    notices: Vec<String>,
    /// The `error_code` of each notice.
    codes: Vec<String>,
}

/// The words of the gateway's notices about the MCM's own life.
fn is_notice(v: &Value) -> bool {
    v["error_status"] == "ERROR"
        && v["error_message"]
            .as_str()
            .is_some_and(|m| m.contains("shutting down") || m.starts_with("mcm-rt"))
}

impl Conn {
    fn connect(addr: SocketAddr) -> Conn {
        let stream = TcpStream::connect(addr).expect("connect");
        stream.set_read_timeout(Some(WAIT)).unwrap();
        let reader = BufReader::new(stream.try_clone().unwrap());
        Conn {
            stream,
            reader,
            notices: Vec::new(),
            codes: Vec::new(),
        }
    }

    /// The next line; `None` when the connection closed.
    fn line(&mut self) -> Option<Value> {
        let mut l = String::new();
        match self.reader.read_line(&mut l) {
            Ok(0) | Err(_) => None,
            Ok(_) => Some(serde_json::from_str(&l).unwrap_or_else(|e| panic!("{e}: {l:?}"))),
        }
    }

    /// Send `cmd` and read its result, keeping notices aside; `None` when the connection
    /// closed first.
    fn try_request(&mut self, cmd: &str) -> Option<Value> {
        self.stream.write_all(format!("{cmd}\n").as_bytes()).ok()?;
        loop {
            let v = self.line()?;
            if is_notice(&v) {
                self.keep(&v);
                continue;
            }
            return Some(v);
        }
    }

    fn request(&mut self, cmd: &str) -> Value {
        self.try_request(cmd).expect("connection closed")
    }

    /// Read until the server closes the connection, keeping the notices.
    fn drain(&mut self) {
        while let Some(v) = self.line() {
            if is_notice(&v) {
                self.keep(&v);
            }
        }
    }

    fn keep(&mut self, notice: &Value) {
        self.notices
            .push(notice["error_message"].as_str().unwrap().to_string());
        self.codes.push(
            notice["error_code"]
                .as_str()
                .unwrap_or("(none)")
                .to_string(),
        );
    }
}

fn six(v: &Value) -> [f64; 6] {
    std::array::from_fn(|i| {
        v[i].as_f64()
            .unwrap_or_else(|| panic!("not 6 numbers: {v}"))
    })
}

fn assert_ok(v: &Value) {
    assert_eq!(v["error_status"], "OK", "{v}");
}

const DETAIL: &str = r#"{"command":"status","arguments":{"detail":true}}"#;

fn wait_drives_online(c: &mut Conn) {
    let deadline = Instant::now() + WAIT;
    loop {
        let s = c.request(DETAIL);
        if s["detail"]["drive_online"]
            .as_array()
            .is_some_and(|a| a.iter().all(|x| x == true))
        {
            return;
        }
        assert!(Instant::now() < deadline, "drives not online: {s}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn sigterm_while_moving_stops_the_arm_disables_the_drives_and_tells_every_client() {
    let mut l = Launcher::start("sigterm");
    let mut c = Conn::connect(l.json);
    let mut watcher = Conn::connect(l.json);
    // A person at the text HMI: everything it is sent until the gateway closes it.
    let hmi = TcpStream::connect(l.hmi).expect("connect to the HMI");
    hmi.set_read_timeout(Some(WAIT)).unwrap();
    let hmi_text = std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = std::io::Read::read_to_end(&mut &hmi, &mut bytes);
        String::from_utf8_lossy(&bytes).into_owned()
    });
    wait_drives_online(&mut c);
    assert_ok(&c.request(r#"{"command":"calibrate"}"#));
    assert_eq!(c.request(r#"{"command":"pvt"}"#)["operating_mode"], "PVT");
    // Axis 1 at half its 90 deg/s, towards a target it will not reach before the stop.
    let far = json!({"command": "move_axis",
        "arguments": {"axis_index": 1, "target_position": 160.0, "velocity_factor": 0.5}});
    assert_ok(&c.request(&far.to_string()));
    let deadline = Instant::now() + WAIT;
    loop {
        let t = c.request(r#"{"command":"sim"}"#);
        if (six(&t["true_velocity"])[0] - 45.0).abs() < 1.0 {
            break;
        }
        assert!(Instant::now() < deadline, "not at 45 deg/s: {t}");
    }

    l.signal(libc::SIGTERM);
    // Follow the stop from a client until the gateway closes the connection: the last
    // answers are the last state mcm-rt published.
    let (mut last_truth, mut last_status) = (None, None);
    let mut saw_shutting_down_while_moving = false;
    let deadline = Instant::now() + WAIT;
    while Instant::now() < deadline {
        let Some(t) = c.try_request(r#"{"command":"sim"}"#) else {
            break;
        };
        let Some(s) = c.try_request(DETAIL) else {
            break;
        };
        if t["result_type"] == "sim" {
            last_truth = Some(six(&t["true_velocity"]));
        }
        if s["result_type"] == "status" {
            if s["detail"]["shutting_down"] == true && last_truth.is_some_and(|v| v[0].abs() > 1.0)
            {
                saw_shutting_down_while_moving = true;
            }
            last_status = Some(s);
        }
    }
    c.drain();
    assert!(l.wait_exit().success(), "the launcher exits cleanly");

    let truth = last_truth.expect("sim answered during the stop");
    assert!(
        truth.iter().all(|v| v.abs() < 0.5),
        "true velocity at the end: {truth:?}"
    );
    let s = last_status.expect("status answered during the stop");
    assert_eq!(s["detail"]["shutting_down"], true, "{s}");
    assert_eq!(s["operating_mode"], "OFF", "{s}");
    assert_eq!(
        s["detail"]["drive_enabled"],
        json!([false, false, false, false, false, false]),
        "{s}"
    );
    assert!(
        saw_shutting_down_while_moving,
        "the state said so while the arm still moved"
    );

    // The log: one line with the time it took and the result.
    let line = l.wait_log("controlled stop took");
    assert!(
        line.contains("arm at standstill, drives disabled"),
        "{line}"
    );
    // Every client was told: mcm-rt shutting down, then the MCM's own shutdown.
    watcher.drain();
    for conn in [&c, &watcher] {
        assert!(
            conn.notices
                .iter()
                .any(|n| n.starts_with("mcm-rt is shutting down")),
            "{:?}",
            conn.notices
        );
        // The launcher stops the gateway right after mcm-rt exited: the gateway still says
        // so before its own last line.
        let n = &conn.notices;
        assert!(n.len() >= 2, "{n:?}");
        assert!(
            n[n.len() - 2].starts_with("mcm-rt stopped after its controlled stop"),
            "{n:?}"
        );
        assert!(
            n.last()
                .is_some_and(|n| n.starts_with("the MCM is shutting down")),
            "{n:?}"
        );
        let codes = &conn.codes;
        assert!(codes.iter().any(|c| c == "core_stopping"), "{codes:?}");
        assert_eq!(
            codes[codes.len() - 2..],
            ["core_stopped", "gateway_stopping"],
            "{n:?}"
        );
    }
    let hmi_text = hmi_text.join().unwrap();
    let stopping = hmi_text
        .find("ERROR [core_stopping]: mcm-rt is shutting down")
        .expect(&hmi_text);
    let bye = hmi_text
        .rfind("ERROR [gateway_stopping]: the MCM is shutting down")
        .expect(&hmi_text);
    assert!(stopping < bye, "{hmi_text}");
}

#[test]
fn kill_9_of_the_launcher_takes_mcm_rt_and_the_gateway_with_it() {
    let mut l = Launcher::start("kill9");
    let (rt, gw) = (l.rt_pid, l.gateway_pid);
    l.signal(libc::SIGKILL);
    l.wait_exit();
    wait_gone(gw, "mcm-gateway");
    wait_gone(rt, "mcm-rt");
    // mcm-rt stopped in order (its controlled stop), not killed.
    l.wait_log("controlled stop took");
}

/// Whether `pid` is stopped (`T` in `/proc/<pid>/stat`).
fn stopped(pid: i32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|s| {
        s.rsplit(')')
            .next()
            .unwrap_or("")
            .trim_start()
            .starts_with('T')
    })
}

/// Wait (bounded) until `pid` is stopped (`want`) or runs again.
fn wait_stopped(pid: i32, want: bool) {
    let deadline = Instant::now() + WAIT;
    while stopped(pid) != want {
        assert!(
            Instant::now() < deadline,
            "pid {pid} not {} within {WAIT:?}",
            if want { "stopped" } else { "continued" }
        );
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Stopped and continued 20 times (Ctrl-Z and `fg`, a debugger), the gateway goes on: the same
/// process keeps serving a client's `status` with the core's newest cycles, and its wait for
/// the core's state event logs no failure.
#[test]
fn the_gateway_stopped_and_continued_20_times_keeps_serving() {
    let l = Launcher::start("stop-cont");
    let mut c = Conn::connect(l.json);
    wait_drives_online(&mut c);
    let gw = l.gateway_pid;
    for round in 0..20 {
        let before = c.request(DETAIL)["detail"]["cycle"]
            .as_u64()
            .expect("cycle");
        // SAFETY: the gateway this test's launcher started.
        unsafe { libc::kill(gw, libc::SIGSTOP) };
        wait_stopped(gw, true);
        // SAFETY: as above.
        unsafe { libc::kill(gw, libc::SIGCONT) };
        wait_stopped(gw, false);
        let deadline = Instant::now() + WAIT;
        loop {
            let s = c.request(DETAIL);
            assert_eq!(s["result_type"], "status", "round {round}: {s}");
            if s["detail"]["cycle"].as_u64().expect("cycle") > before {
                break;
            }
            assert!(
                Instant::now() < deadline,
                "round {round}: no cycle after {before} within {WAIT:?}: {s}"
            );
        }
    }
    assert!(!gone(gw), "the gateway exited");
    let restarted = l
        .stdout
        .try_iter()
        .find(|line| line.starts_with(McmReady::PREFIX));
    assert_eq!(restarted, None, "the launcher restarted the gateway");
    let log = l.log.lock().unwrap();
    assert!(
        !log.iter().any(|line| line.contains("mcm-gateway")
            && (line.contains("cannot wait") || line.contains("exited"))),
        "{log:#?}"
    );
}

#[test]
fn kill_9_of_mcm_rt_tells_clients_the_core_stopped_before_the_launcher_stops_the_gateway() {
    let mut l = Launcher::start("rt-kill9");
    let mut c = Conn::connect(l.json);
    // The gateway reads the core's state: the client is connected to a running MCM.
    assert_eq!(c.request(DETAIL)["result_type"], "status");
    // SAFETY: the mcm-rt this test's launcher started.
    unsafe { libc::kill(l.rt_pid, libc::SIGKILL) };
    c.drain();
    let status = l.wait_exit();
    assert!(!status.success(), "a dead core is an error: {status}");
    l.wait_log("mcm-rt exited unexpectedly");
    // The launcher stopped the gateway at once; the client still heard why: the core vanished
    // (not a shutdown of mcm-rt), then the gateway's own last line.
    let n = &c.notices;
    assert!(n.len() >= 2, "{n:?}");
    assert!(
        n[n.len() - 2].starts_with("mcm-rt stopped publishing its state without shutting down"),
        "{n:?}"
    );
    assert!(
        n[n.len() - 1].starts_with("the MCM is shutting down"),
        "{n:?}"
    );
    assert!(
        !n.iter().any(|m| m.starts_with("mcm-rt is shutting down")),
        "mcm-rt was killed, not asked to stop: {n:?}"
    );
    let codes = &c.codes;
    assert_eq!(
        codes[codes.len() - 2..],
        ["core_vanished", "gateway_stopping"],
        "{n:?}"
    );
}

#[test]
fn a_gateway_that_keeps_dying_is_restarted_with_a_back_off_and_mcm_rt_keeps_running() {
    let mut l = Launcher::start("gw-dies");
    let rt = l.rt_pid;
    let mut last_cycle = 0u64;
    // The launcher's back-off: the first four waits, each longer than the one before.
    let waits: Vec<Duration> = (1..=4).map(|n| GATEWAY_RESTART.delay(n)).collect();
    assert!(waits.windows(2).all(|w| w[0] < w[1]), "{waits:?}");
    for (round, wait) in waits.iter().enumerate() {
        let mut c = Conn::connect(l.json);
        let cycle = c.request(DETAIL)["detail"]["cycle"]
            .as_u64()
            .expect("cycle");
        assert!(
            cycle > last_cycle,
            "round {round}: the core's state goes on ({cycle})"
        );
        last_cycle = cycle;
        let gw = l.gateway_pid;
        // SAFETY: the gateway this test's launcher started.
        unsafe { libc::kill(gw, libc::SIGKILL) };
        l.wait_ready();
        assert_ne!(l.gateway_pid, gw, "a new gateway");
        assert_eq!(l.rt_pid, rt, "the same mcm-rt");
        let line = l.wait_log(&format!("restarting the gateway in {wait:?}"));
        assert!(line.contains("mcm-rt keeps running"), "{line}");
    }
    assert!(alive(rt) && !gone(rt));
    let mut c = Conn::connect(l.json);
    let cycle = c.request(DETAIL)["detail"]["cycle"].as_u64().unwrap();
    assert!(cycle > last_cycle);
}

#[test]
fn a_config_that_switches_the_overspeed_check_off_is_refused_at_start() {
    let config = config_file("overspeed", |base| {
        let text = base.replace("overspeed_factor = 1.1", "overspeed_factor = 100.0");
        assert!(text.contains("overspeed_factor = 100.0"));
        text
    });
    let instance = unique_instance("overspeed");
    let (mut child, _stdout, log) = spawn(&instance, &["--config", config.path()]);
    let deadline = Instant::now() + WAIT;
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(Instant::now() < deadline, "mcm did not refuse the config");
        std::thread::sleep(Duration::from_millis(10));
    };
    drop(config);
    assert!(!status.success());
    let deadline = Instant::now() + WAIT;
    loop {
        let found = log.lock().unwrap().iter().any(|l| {
            l.contains("config key `safety.overspeed_factor` = 100 is not allowed: 1..=1.5")
        });
        if found {
            break;
        }
        assert!(Instant::now() < deadline, "log: {:#?}", log.lock().unwrap());
        std::thread::sleep(Duration::from_millis(10));
    }
}
