//! The real `mcm-rt` and `mcm-gateway` (as `mcm rt` and `mcm gateway`, the same programs)
//! started the way systemd starts a `Type=notify` unit with `WatchdogSec=`: `NOTIFY_SOCKET`
//! names a datagram socket this test listens on, `WATCHDOG_USEC` the watchdog's timeout. Each
//! says `READY=1` with its ready line as `STATUS=`, pings the watchdog (`WATCHDOG=1`, every half
//! of the timeout; the core only while its cycle runs), and says `STOPPING=1` at SIGTERM before
//! it exits. Every wait is bounded.

use crate::common;

use std::os::unix::net::UnixDatagram;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A socket in the role of systemd's notification socket.
struct Systemd {
    socket: UnixDatagram,
    dir: PathBuf,
}

impl Systemd {
    fn new(tag: &str) -> Systemd {
        let dir = std::env::temp_dir().join(common::unique_instance(tag));
        std::fs::create_dir_all(&dir).unwrap();
        let socket = UnixDatagram::bind(dir.join("notify")).unwrap();
        socket
            .set_read_timeout(Some(Duration::from_millis(200)))
            .unwrap();
        Systemd { socket, dir }
    }

    /// Start `mcm ARGS` as systemd would with a watchdog of `watchdog`.
    fn start(&self, args: &[&str], watchdog: Duration) -> Child {
        Command::new(env!("CARGO_BIN_EXE_mcm"))
            .args(args)
            .env("NOTIFY_SOCKET", self.dir.join("notify"))
            .env("WATCHDOG_USEC", watchdog.as_micros().to_string())
            .env_remove("WATCHDOG_PID")
            .stdout(Stdio::null())
            .stderr(Stdio::inherit())
            .spawn()
            .unwrap()
    }

    /// The notifications until one contains `until` (that one included), within the test's
    /// wait; panics with what came.
    fn until(&self, until: &str) -> Vec<String> {
        let deadline = Instant::now() + common::WAIT;
        let mut got = Vec::new();
        let mut buf = [0u8; 4096];
        while Instant::now() < deadline {
            if let Ok(n) = self.socket.recv(&mut buf) {
                let msg = String::from_utf8_lossy(&buf[..n]).into_owned();
                let done = msg.contains(until);
                got.push(msg);
                if done {
                    return got;
                }
            }
        }
        panic!("no {until:?} within {:?}; got {got:#?}", common::WAIT);
    }
}

impl Drop for Systemd {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// SIGTERM to `child`, then its exit within the test's wait.
fn terminate(child: &mut Child) -> std::process::ExitStatus {
    // SAFETY: kill only sends a signal to the child this test started.
    unsafe { libc::kill(child.id() as i32, libc::SIGTERM) };
    let deadline = Instant::now() + common::WAIT;
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        assert!(
            Instant::now() < deadline,
            "still running {:?} after SIGTERM",
            common::WAIT
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn the_core_notifies_ready_the_watchdog_and_its_controlled_stop() {
    let systemd = Systemd::new("notify-rt");
    let instance = common::unique_instance("nrt");
    let mut core = systemd.start(
        &["rt", "--instance", &instance, "--allow-non-realtime"],
        Duration::from_millis(400),
    );
    let ready = systemd.until("READY=1");
    let last = ready.last().unwrap();
    assert!(
        last.contains(&format!("STATUS=mcm-rt ready instance={instance} bus=sim")),
        "{ready:#?}"
    );
    // Pinged every 200 ms while the cycle runs: three pings take about 0.6 s.
    for _ in 0..3 {
        systemd.until("WATCHDOG=1");
    }
    let status = terminate(&mut core);
    let stopping = systemd.until("STOPPING=1");
    assert!(
        stopping.last().unwrap().contains("STATUS=controlled stop"),
        "{stopping:#?}"
    );
    assert!(
        status.success(),
        "mcm-rt after its controlled stop: {status}"
    );
    let _ = std::fs::remove_file(mcm_shared::service::sim_state_path(&instance));
}

#[test]
fn the_gateway_notifies_ready_once_it_listens_the_watchdog_and_its_stop() {
    let systemd = Systemd::new("notify-gw");
    let instance = common::unique_instance("ngw");
    let mut gateway = systemd.start(
        &[
            "gateway",
            "--instance",
            &instance,
            "--bind",
            "127.0.0.1",
            "--json-port",
            "0",
            "--hmi-port",
            "0",
            "--http-port",
            "0",
        ],
        Duration::from_millis(400),
    );
    let ready = systemd.until("READY=1");
    let status = ready.last().unwrap();
    let line = status
        .lines()
        .find_map(|l| l.strip_prefix("STATUS="))
        .unwrap_or_else(|| panic!("a STATUS= line: {ready:#?}"));
    let listening: mcm_shared::ready::GatewayReady = line.parse().unwrap();
    // Ready means listening: the JSON port takes a connection now.
    std::net::TcpStream::connect(listening.json).unwrap();
    for _ in 0..3 {
        systemd.until("WATCHDOG=1");
    }
    let exit = terminate(&mut gateway);
    systemd.until("STOPPING=1");
    assert!(exit.success(), "mcm-gateway after SIGTERM: {exit}");
}
