//! Test harness: start the real `mcm` launcher (both processes) on free ports with a unique
//! instance name (through the client library's launcher, `mcm_client::launch`), talk to it
//! over TCP, stop it on drop. Every wait is bounded.

#![allow(dead_code)]

pub mod built;
pub mod deb;
pub mod flight;
pub mod machine;
pub mod netns;
pub mod python;
pub mod ros2;
pub mod secure_peer;
pub mod square;
pub mod tcp;
pub mod virtual_arm;
pub mod vm;

use mcm_client::launch::SimulatedMcm;
use mcm_shared::service::sim_state_path;
use serde_json::Value;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Shutdown, SocketAddr, TcpStream};
use std::process::Stdio;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

static COUNTER: AtomicU32 = AtomicU32::new(0);

/// How long any single wait may take before the test fails.
pub const WAIT: Duration = Duration::from_secs(20);

/// The value of the environment variable `name` (a test's count or duration set by hand), or
/// `default` when it is not set; a value that does not parse fails the test naming it.
pub fn env_or<T>(name: &str, default: T) -> T
where
    T: std::str::FromStr,
    T::Err: std::fmt::Display,
{
    std::env::var(name).map_or(default, |v| {
        v.parse().unwrap_or_else(|e| panic!("{name} = {v:?}: {e}"))
    })
}

/// Say that `test` is skipped because `why` (with what would make it run), or fail when the
/// environment variable `CI` is set: CI must run every test. The message goes straight to
/// stderr, past the test harness's output capture, so it shows also when the test passes
/// (`eprintln!` would be captured and dropped). The caller returns right after.
pub fn skip(test: &str, why: &str) {
    if std::env::var_os("CI").is_some() {
        panic!("{test} cannot run: {why}; CI is set, where a skipped test is a failure");
    }
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED {test}: {why} (with CI set this is a failure)"
    );
}

/// The program `name` on `PATH`, if any.
pub fn find_program(name: &str) -> Option<std::path::PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// The number printed right after `before` in `text` (an example's output); panics naming both
/// when it is not there.
pub fn number_after(text: &str, before: &str) -> f64 {
    let rest = &text[text
        .find(before)
        .unwrap_or_else(|| panic!("{before:?} in {text}"))
        + before.len()..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .unwrap_or(rest.len());
    rest[..end]
        .parse()
        .unwrap_or_else(|e| panic!("{before:?}: {e} in {text}"))
}

/// The longest tag an MCM's instance name may be made from ([`Mcm::start_with`]): an instance
/// name has at most 32 characters, and [`unique_instance`]'s `t<pid>-<n>-` takes up to 13 of
/// them (a pid up to Linux's largest, 4194304, and up to 999 names per test process). A longer
/// tag fails every time, not only under a long pid. (Names made for other things, directories
/// and topics, have no such limit.)
pub const MAX_TAG: usize = 32 - 13;

/// A unique instance name for this test process. The test shares the machine from here on
/// ([`machine::share`]): an instance name is the start of an MCM.
pub fn unique_instance(tag: &str) -> String {
    machine::share();
    format!(
        "t{}-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed),
        tag
    )
}

/// A running MCM (launcher + mcm-rt + mcm-gateway); dropping it stops it and removes the
/// simulation state it saved ([`Mcm::stop`] keeps it).
pub struct Mcm {
    /// `None` once stopped by [`Mcm::stop`].
    sim: Option<SimulatedMcm>,
    pub instance: String,
    pub json: SocketAddr,
    pub hmi: SocketAddr,
    pub rt_pid: i32,
    pub gateway_pid: i32,
    /// The ZeroMQ endpoints as bound (`--zmq...` given), e.g. `tcp://127.0.0.1:40123`.
    pub zmq: Option<(String, String)>,
    /// Over SocketCAN (`MCM_TEST_BUS=socketcan`): the virtual arm on the core's interface.
    /// Declared after `sim`, so that it stops after the MCM.
    pub arm: Option<virtual_arm::VirtualArm>,
}

impl Mcm {
    /// Start with the embedded configuration.
    pub fn start(tag: &str) -> Mcm {
        Self::start_with(tag, &[])
    }

    /// Start with extra launcher arguments.
    pub fn start_with(tag: &str, extra: &[&str]) -> Mcm {
        assert!(
            tag.len() <= MAX_TAG,
            "instance tag {tag:?} has {} characters; at most {MAX_TAG} leave room for the pid and \
             the count in an instance name of 32",
            tag.len()
        );
        Self::start_named(&unique_instance(tag), extra)
    }

    /// Start with the instance name `instance` and extra launcher arguments.
    pub fn start_named(instance: &str, extra: &[&str]) -> Mcm {
        machine::share();
        let mut extra: Vec<&str> = extra.to_vec();
        let arm = virtual_arm::socketcan().then(|| {
            let at = extra.iter().position(|a| *a == "--config");
            let text = match at {
                Some(i) => std::fs::read_to_string(extra[i + 1]).unwrap(),
                None => mcm_shared::config::PROB2_DEFAULT_TOML.to_string(),
            };
            if let Some(i) = at {
                extra.drain(i..i + 2);
            }
            virtual_arm::VirtualArm::start(&text)
        });
        Self::start_on(arm, instance, &extra)
    }

    /// Start over the virtual arm `arm` (its interface and configuration; none: the in-process
    /// simulated bus) with the instance name `instance` and extra launcher arguments (without
    /// `--config` when there is an arm).
    pub fn start_on(arm: Option<virtual_arm::VirtualArm>, instance: &str, extra: &[&str]) -> Mcm {
        machine::share();
        let mut extra: Vec<&str> = extra.to_vec();
        if let Some(a) = &arm {
            extra.extend(["--config", a.config.path()]);
        }
        let extra: Vec<&std::ffi::OsStr> = extra.iter().map(|a| a.as_ref()).collect();
        let sim = SimulatedMcm::start_echoing(
            &virtual_arm::mcm_binary(),
            instance,
            &extra,
            Stdio::inherit(),
            WAIT,
            Some("[mcm] "),
        )
        .unwrap_or_else(|e| panic!("start mcm: {e}"));
        let mut mcm = Mcm {
            sim: Some(sim),
            instance: instance.to_string(),
            json: "0.0.0.0:0".parse().unwrap(),
            hmi: "0.0.0.0:0".parse().unwrap(),
            rt_pid: 0,
            gateway_pid: 0,
            zmq: None,
            arm,
        };
        mcm.take_addresses();
        mcm
    }

    /// The addresses and pids of the launcher's last ready line.
    fn take_addresses(&mut self) {
        let s = self.sim.as_ref().expect("running until stopped");
        (self.json, self.hmi) = (s.json, s.hmi);
        (self.rt_pid, self.gateway_pid) = (s.rt_pid, s.gateway_pid);
        self.zmq = s.zmq.clone().map(|z| (z.router, z.publish));
        if let Some(a) = &self.arm {
            a.serve_clients_of(self.json);
        }
    }

    /// Wait for the launcher's next ready line (after it restarted the gateway) and take the
    /// addresses and pids from it.
    pub fn wait_ready(&mut self) {
        self.sim
            .as_mut()
            .expect("running until stopped")
            .wait_ready(WAIT)
            .unwrap_or_else(|e| panic!("the launcher's ready line: {e}"));
        self.take_addresses();
    }

    /// The next stdout line starting with `prefix` (other lines are skipped).
    pub fn wait_line(&self, prefix: &str) -> String {
        self.sim()
            .wait_line(prefix, WAIT)
            .unwrap_or_else(|e| panic!("{e}"))
    }

    /// A new JSON client.
    pub fn client(&self) -> Client {
        Client::connect(self.json)
    }

    /// Stop with SIGTERM; returns the launcher's exit status. The simulation state mcm-rt
    /// saved is kept for a restart of the same instance.
    pub fn stop(mut self) -> std::process::ExitStatus {
        let sim = self.sim.take().expect("running until stopped");
        sim.stop().unwrap_or_else(|e| panic!("{e}"))
    }

    fn sim(&self) -> &SimulatedMcm {
        self.sim.as_ref().expect("running until stopped")
    }
}

/// A test that ends without [`Mcm::stop`] still stops the MCM with SIGTERM and fails when it
/// does not stop in time (a shutdown that hangs is a bug, not only a slow test); its
/// simulation state is removed. When the test already fails, the MCM is stopped as well as it
/// can be, without a second panic.
impl Drop for Mcm {
    fn drop(&mut self) {
        let Some(sim) = self.sim.take() else {
            return;
        };
        let stopped = sim.stop();
        let _ = std::fs::remove_file(sim_state_path(&self.instance));
        if let Err(e) = stopped
            && !std::thread::panicking()
        {
            panic!("the MCM did not stop: {e}");
        }
    }
}

/// A configuration file written for one test, in the temp directory; removed on drop.
pub struct TempConfig(std::path::PathBuf);

impl TempConfig {
    /// The file's path, for `--config`.
    pub fn path(&self) -> &str {
        self.0.to_str().unwrap()
    }
}

impl Drop for TempConfig {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// Write `edit(deploy/prob2.toml)` (the P-Rob2's configuration as the binaries embed it) to a
/// new file named after `tag`.
pub fn config_file(tag: &str, edit: impl FnOnce(&str) -> String) -> TempConfig {
    let path = std::env::temp_dir().join(format!("{}.toml", unique_instance(tag)));
    std::fs::write(&path, edit(mcm_shared::config::PROB2_DEFAULT_TOML)).unwrap();
    TempConfig(path)
}

/// Whether a process exists.
pub fn alive(pid: i32) -> bool {
    // SAFETY: signal 0 only checks existence.
    unsafe { libc::kill(pid, 0) == 0 }
}

/// A JSON protocol client speaking raw bytes.
pub struct Client {
    stream: TcpStream,
    reader: BufReader<TcpStream>,
    /// The virtual arm that answers `sim` requests, over SocketCAN ([`virtual_arm`]).
    arm: Option<SocketAddr>,
}

impl Client {
    pub fn connect(addr: SocketAddr) -> Client {
        Client::on(TcpStream::connect(addr).expect("connect"))
    }

    /// A client on a connection made elsewhere (e.g. [`netns::Netns::connect`]).
    pub fn on(stream: TcpStream) -> Client {
        stream.set_nodelay(true).unwrap();
        stream.set_read_timeout(Some(WAIT)).unwrap();
        let reader = BufReader::new(stream.try_clone().unwrap());
        let arm = stream.peer_addr().ok().and_then(virtual_arm::arm_behind);
        Client {
            stream,
            reader,
            arm,
        }
    }

    /// The virtual arm that answers this client's `sim` requests, over SocketCAN.
    pub fn virtual_arm(&self) -> Option<SocketAddr> {
        self.arm
    }

    /// Send raw bytes.
    pub fn send_raw(&mut self, bytes: &[u8]) {
        self.stream.write_all(bytes).unwrap();
    }

    /// Read one result line.
    pub fn recv(&mut self) -> Value {
        let mut line = String::new();
        let n = self
            .reader
            .read_line(&mut line)
            .expect("read a result line");
        assert!(n > 0, "connection closed while waiting for a result");
        assert!(line.ends_with('\n'), "results end with a newline: {line:?}");
        serde_json::from_str(&line).unwrap_or_else(|e| panic!("result is not JSON ({e}): {line:?}"))
    }

    /// Read one result line, skipping spontaneous results that do not match `keep`.
    pub fn recv_matching(&mut self, keep: impl Fn(&Value) -> bool) -> Value {
        loop {
            let v = self.recv();
            if keep(&v) {
                return v;
            }
        }
    }

    /// Send one command line and read its result (a `sim` request to the virtual arm, over
    /// SocketCAN).
    pub fn request(&mut self, json: &str) -> Value {
        if let Some(arm) = self.arm
            && virtual_arm::is_sim(json)
        {
            return virtual_arm::ask(arm, json);
        }
        self.send_raw(format!("{json}\n").as_bytes());
        self.recv()
    }

    /// True when the server closed the connection (reads EOF within the wait).
    pub fn closed(&mut self) -> bool {
        let mut buf = [0u8; 1];
        matches!(self.reader.read(&mut buf), Ok(0))
    }

    /// Poll `status` (detail) until `pred` holds; panics after [`WAIT`].
    pub fn wait_status(&mut self, what: &str, pred: impl Fn(&Value) -> bool) -> Value {
        let deadline = Instant::now() + WAIT;
        loop {
            let s = self.request(r#"{"command":"status","arguments":{"detail":true}}"#);
            if pred(&s) {
                return s;
            }
            assert!(
                Instant::now() < deadline,
                "timed out waiting for {what}; last status: {s}"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Wait until every drive is online (the drives boot when mcm-rt starts).
    pub fn wait_drives_online(&mut self) -> Value {
        self.wait_status("all drives online", |s| {
            s["detail"]["drive_online"]
                .as_array()
                .is_some_and(|a| a.iter().all(|x| x == true))
        })
    }

    /// The simulation's ground truth (`sim`): true joint angles and velocities [deg, deg/s].
    pub fn truth(&mut self) -> ([f64; 6], [f64; 6]) {
        let r = self.request(r#"{"command":"sim"}"#);
        assert_eq!(r["result_type"], "sim", "{r}");
        (six(&r["true_position"]), six(&r["true_velocity"]))
    }

    /// Poll the truth until `done(position, velocity)`; returns it; panics after [`WAIT`].
    pub fn wait_truth(
        &mut self,
        what: &str,
        done: impl Fn(&[f64; 6], &[f64; 6]) -> bool,
    ) -> ([f64; 6], [f64; 6]) {
        let deadline = Instant::now() + WAIT;
        loop {
            let (p, v) = self.truth();
            if done(&p, &v) {
                return (p, v);
            }
            assert!(
                Instant::now() < deadline,
                "timed out waiting for {what}; true position {p:?}, velocity {v:?}"
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

/// Start an MCM, wait for its drives and calibrate every axis (straight from OFF): the arm
/// ends in HOLD at zero, controlled by the client returned.
pub fn calibrated(tag: &str) -> (Mcm, Client) {
    let mcm = Mcm::start(tag);
    let mut c = mcm.client();
    c.wait_drives_online();
    assert_ok(&c.request(r#"{"command":"calibrate"}"#));
    (mcm, c)
}

/// A spontaneous safety error: a generic ERROR that names a check.
pub fn is_event(v: &Value) -> bool {
    v["result_type"] == "generic" && v["error_status"] == "ERROR" && v.get("check").is_some()
}

/// A JSON client that keeps spontaneous results apart from replies. A reader thread parses
/// every line; spontaneous safety errors that arrive while a reply is awaited are kept in
/// `events` (in order), other results nobody asked for (the status results of a
/// TORQUE_CONTROL session, replies to commands sent without waiting) in `unasked`.
pub struct EventClient {
    stream: TcpStream,
    /// The virtual arm that answers `sim` requests, over SocketCAN ([`virtual_arm`]).
    arm: Option<SocketAddr>,
    lines: mpsc::Receiver<Value>,
    pub events: Vec<Value>,
    /// Events already returned by [`EventClient::wait_event`].
    taken: usize,
    pub unasked: Vec<Value>,
}

impl EventClient {
    pub fn connect(addr: SocketAddr) -> EventClient {
        let stream = TcpStream::connect(addr).expect("connect");
        stream.set_nodelay(true).unwrap();
        let reader = BufReader::new(stream.try_clone().unwrap());
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in reader.lines() {
                let Ok(line) = line else { break };
                let v = serde_json::from_str(&line)
                    .unwrap_or_else(|e| panic!("result is not JSON ({e}): {line:?}"));
                if tx.send(v).is_err() {
                    break;
                }
            }
        });
        EventClient {
            stream,
            arm: virtual_arm::arm_behind(addr),
            lines: rx,
            events: Vec::new(),
            taken: 0,
            unasked: Vec::new(),
        }
    }

    /// Send one command line without waiting for its result.
    pub fn send(&mut self, json: &str) {
        assert!(
            self.arm.is_none() || !virtual_arm::is_sim(json),
            "over SocketCAN a `sim` request goes to the virtual arm: use `request`, not `send`"
        );
        self.stream
            .write_all(format!("{json}\n").as_bytes())
            .expect("send a command");
    }

    /// The next line within `timeout` (`None` when none came).
    pub fn next(&mut self, timeout: Duration) -> Option<Value> {
        match self.lines.recv_timeout(timeout) {
            Ok(v) => Some(v),
            Err(mpsc::RecvTimeoutError::Timeout) => None,
            Err(mpsc::RecvTimeoutError::Disconnected) => panic!("the connection was closed"),
        }
    }

    /// Send a command and return its result (spontaneous errors go to `events`).
    pub fn request_within(&mut self, json: &str, wait: Duration) -> Value {
        if let Some(arm) = self.arm
            && virtual_arm::is_sim(json)
        {
            // Take in what the gateway sent meanwhile, as a request through the gateway
            // would: a test that polls the truth in a loop waiting for an error sees it.
            while let Ok(v) = self.lines.try_recv() {
                if is_event(&v) {
                    self.events.push(v);
                } else {
                    self.unasked.push(v);
                }
            }
            return virtual_arm::ask(arm, json);
        }
        self.send(json);
        self.result_within(json, wait)
    }

    /// The result of the command `json` sent before ([`EventClient::send`]); spontaneous
    /// errors that come first go to `events`.
    pub fn result_within(&mut self, json: &str, wait: Duration) -> Value {
        loop {
            let v = self
                .next(wait)
                .unwrap_or_else(|| panic!("no result for {json} within {wait:?}"));
            if is_event(&v) {
                self.events.push(v);
            } else {
                return v;
            }
        }
    }

    /// [`EventClient::request_within`] [`WAIT`].
    pub fn request(&mut self, json: &str) -> Value {
        self.request_within(json, WAIT)
    }

    /// The next spontaneous safety error not yet taken; panics after `wait`.
    pub fn wait_event(&mut self, what: &str, wait: Duration) -> Value {
        let deadline = Instant::now() + wait;
        while self.taken == self.events.len() {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.next(left) {
                Some(v) if is_event(&v) => self.events.push(v),
                Some(v) => self.unasked.push(v),
                None => panic!("no spontaneous error ({what}) within {wait:?}"),
            }
        }
        self.taken += 1;
        self.events[self.taken - 1].clone()
    }

    /// Every line until the server closes the connection; panics when it is still open
    /// after `wait`.
    pub fn until_closed(&mut self, wait: Duration) -> Vec<Value> {
        let deadline = Instant::now() + wait;
        let mut got = Vec::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(v) => got.push(v),
                Err(mpsc::RecvTimeoutError::Disconnected) => return got,
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    panic!("the connection is still open after {wait:?}: {got:?}")
                }
            }
        }
    }

    /// Every line that arrives within `window` (nothing is asked meanwhile).
    pub fn gather(&mut self, window: Duration) -> Vec<Value> {
        let deadline = Instant::now() + window;
        let mut got = Vec::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return got;
            }
            if let Some(v) = self.next(left) {
                got.push(v);
            }
        }
    }
}

impl Drop for EventClient {
    fn drop(&mut self) {
        let _ = self.stream.shutdown(Shutdown::Both);
    }
}

/// The robot's time of a status result [s] (`axis_states.time`, the cycle's clock).
pub fn time_of(s: &Value) -> f64 {
    s["axis_states"]["time"][0]
        .as_f64()
        .unwrap_or_else(|| panic!("no time in {s}"))
}

/// The `move_axis` command line (`axis` 1-based).
pub fn move_axis(axis: usize, target: f64, velocity_factor: f64) -> String {
    serde_json::json!({"command": "move_axis",
           "arguments": {"axis_index": axis, "target_position": target,
                         "velocity_factor": velocity_factor}})
    .to_string()
}

/// `pvt` with points 20 ms apart: one cycle at 50 Hz, the rate of the test guest over SocketCAN
/// (`MCM_TEST_EMULATED`; the manual's default of 10 ms is less than a cycle there and refused),
/// for tests that move in PVT without streaming points.
pub const PVT_ANY_RATE: &str = r#"{"command":"pvt","arguments":{"dt":0.02}}"#;

/// The `move_all` command line.
pub fn move_all(target: &[f64; 6], velocity_factor: f64) -> String {
    serde_json::json!({"command": "move_all",
           "arguments": {"target_positions": target, "velocity_factor": velocity_factor}})
    .to_string()
}

/// The `error_status` of a generic result.
pub fn is_error(v: &Value) -> bool {
    v["result_type"] == "generic" && v["error_status"] == "ERROR"
}

/// Assert a generic ERROR whose message contains every one of `words`.
pub fn assert_error(v: &Value, words: &[&str]) {
    assert!(is_error(v), "expected a generic ERROR, got {v}");
    let msg = v["error_message"].as_str().unwrap_or_default();
    for w in words {
        assert!(msg.contains(w), "error message {msg:?} lacks {w:?}");
    }
}

/// Six numbers from a JSON array (panics naming the value otherwise).
pub fn six(v: &Value) -> [f64; 6] {
    let a = v
        .as_array()
        .unwrap_or_else(|| panic!("expected an array of 6 numbers, got {v}"));
    assert_eq!(a.len(), 6, "expected 6 numbers, got {v}");
    std::array::from_fn(|i| a[i].as_f64().unwrap_or_else(|| panic!("not a number: {v}")))
}

/// The largest absolute difference between two six-vectors.
pub fn max_diff(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The angle [rad] between two orientations written as quaternions `[x, y, z, w]` (q and -q
/// are one rotation). Each is normalised first (the protocol's figures are rounded, so their
/// norm is 1 only to about 1e-6), and the angle is taken with `atan2` of the relative
/// rotation's vector and scalar parts: `acos` of a dot product near 1 would turn that
/// rounding into milliradians.
pub fn orientation_angle(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    let unit = |q: &[f64; 4]| {
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        q.map(|x| x / n)
    };
    let ([ax, ay, az, aw], [bx, by, bz, bw]) = (unit(a), unit(b));
    // conj(a) * b: the rotation from a to b.
    let w = aw * bw + ax * bx + ay * by + az * bz;
    let v = [
        aw * bx - bw * ax - (ay * bz - az * by),
        aw * by - bw * ay - (az * bx - ax * bz),
        aw * bz - bw * az - (ax * by - ay * bx),
    ];
    let v = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    2.0 * v.atan2(w.abs())
}

/// The largest absolute value of a six-vector.
pub fn max_abs(a: &[f64; 6]) -> f64 {
    max_diff(a, &[0.0; 6])
}

/// Assert a generic OK result.
pub fn assert_ok(v: &Value) {
    assert_eq!(
        v["result_type"], "generic",
        "expected a generic result: {v}"
    );
    assert_eq!(v["error_status"], "OK", "expected OK: {v}");
}

/// Assert a status result in `mode`.
pub fn assert_status(v: &Value, mode: &str) {
    assert_eq!(v["result_type"], "status", "expected a status result: {v}");
    assert_eq!(v["operating_mode"], mode, "{v}");
}
