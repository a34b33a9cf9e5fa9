//! The MCM under test: the `mcm` launcher (mcm-rt + mcm-gateway, simulated robot) started with a
//! unique instance name on free loopback ports, stopped with SIGTERM at the end.

use crate::error::BenchError;
use std::io::{BufRead, BufReader};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Longest wait for the launcher's ready line, and for its exit after SIGTERM.
const START_WAIT: Duration = Duration::from_secs(60);
const STOP_WAIT: Duration = Duration::from_secs(20);

/// A running MCM.
pub struct Mcm {
    child: Child,
    pub instance: String,
    pub json: SocketAddr,
    pub rt_pid: i32,
    pub gateway_pid: i32,
    /// Where the launcher's and its children's stderr goes.
    pub log: PathBuf,
}

/// The value of `key=` in the launcher's ready line (`[json=ADDR hmi=ADDR rt_pid=N ...]`).
pub fn ready_field<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    line.split(|c: char| c.is_whitespace() || c == '[' || c == ']')
        .find_map(|w| w.strip_prefix(key).and_then(|r| r.strip_prefix('=')))
}

/// The `mcm` binary: `explicit`, else the one beside this executable (same target dir).
pub fn locate(explicit: Option<&Path>) -> Result<PathBuf, BenchError> {
    if let Some(p) = explicit {
        return Ok(p.to_path_buf());
    }
    let me = std::env::current_exe()
        .map_err(|e| BenchError::Start(format!("cannot find this executable: {e}")))?;
    let mcm = me.with_file_name("mcm");
    if mcm.is_file() {
        Ok(mcm)
    } else {
        Err(BenchError::Start(format!(
            "no `mcm` binary at {}; build it in the same profile first \
             (`cargo build --release -p mcm -p mcm-bench`, as scripts/bench.sh does) or pass --mcm PATH",
            mcm.display()
        )))
    }
}

impl Mcm {
    /// Start `binary` as instance `instance`, with the configuration file `config` if given.
    pub fn start(binary: &Path, instance: &str, config: Option<&Path>) -> Result<Mcm, BenchError> {
        let log = std::env::temp_dir().join(format!("mcm-bench-{instance}.log"));
        let log_file = std::fs::File::create(&log)
            .map_err(|e| BenchError::Start(format!("cannot create {}: {e}", log.display())))?;
        let mut child = Command::new(binary)
            .args([
                "--instance",
                instance,
                "--bind",
                "127.0.0.1",
                "--json-port",
                "0",
                "--hmi-port",
                "0",
            ])
            .args(
                config
                    .iter()
                    .flat_map(|c| [std::ffi::OsStr::new("--config"), c.as_os_str()]),
            )
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(log_file)
            .spawn()
            .map_err(|e| BenchError::Start(format!("cannot run {}: {e}", binary.display())))?;
        let stdout = child.stdout.take().expect("stdout is piped");
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let mut mcm = Mcm {
            child,
            instance: instance.to_string(),
            json: "127.0.0.1:0".parse().expect("literal address"),
            rt_pid: 0,
            gateway_pid: 0,
            log,
        };
        let deadline = Instant::now() + START_WAIT;
        let line = loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match rx.recv_timeout(left) {
                Ok(l) if l.starts_with("MCM ready") => break l,
                Ok(_) => {}
                Err(_) => {
                    return Err(BenchError::Start(format!(
                        "no ready line from {} within {START_WAIT:?}; see {}",
                        binary.display(),
                        mcm.log.display()
                    )));
                }
            }
        };
        let field = |key: &str| {
            ready_field(&line, key)
                .ok_or_else(|| BenchError::Start(format!("no `{key}=` in the ready line: {line}")))
        };
        let bad = |key: &str| BenchError::Start(format!("bad `{key}=` in the ready line: {line}"));
        mcm.json = field("json")?.parse().map_err(|_| bad("json"))?;
        mcm.rt_pid = field("rt_pid")?.parse().map_err(|_| bad("rt_pid"))?;
        mcm.gateway_pid = field("gateway_pid")?
            .parse()
            .map_err(|_| bad("gateway_pid"))?;
        // Keep draining stdout so the launcher never blocks on a full pipe.
        std::thread::spawn(move || while rx.recv().is_ok() {});
        Ok(mcm)
    }

    /// Stop with SIGTERM (bounded wait, then SIGKILL) and remove the simulation's saved state
    /// and the log (kept when the run ends any other way, for a look at what went wrong).
    pub fn stop(mut self) {
        self.terminate();
        let _ = std::fs::remove_file(&self.log);
    }

    fn terminate(&mut self) {
        if self.child.try_wait().ok().flatten().is_some() {
            return;
        }
        let pid = self.child.id() as i32;
        // SAFETY: signalling our own child process by its pid.
        unsafe { libc::kill(pid, libc::SIGTERM) };
        let deadline = Instant::now() + STOP_WAIT;
        while self.child.try_wait().ok().flatten().is_none() {
            if Instant::now() > deadline {
                eprintln!("mcm-bench: the MCM did not stop within {STOP_WAIT:?}; killing it");
                let _ = self.child.kill();
                let _ = self.child.wait();
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let saved = std::env::temp_dir().join(format!("mcm-sim-{}.state", self.instance));
        let _ = std::fs::remove_file(saved);
    }
}

impl Drop for Mcm {
    fn drop(&mut self) {
        self.terminate();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_fields_of_the_ready_line() {
        let l = "MCM ready (simulated P-Rob2, instance b1): JSON on 127.0.0.1:4000, telnet HMI on \
                 127.0.0.1:4001; Ctrl-C stops. [json=127.0.0.1:4000 hmi=127.0.0.1:4001 rt_pid=12 gateway_pid=13]";
        assert_eq!(ready_field(l, "json"), Some("127.0.0.1:4000"));
        assert_eq!(ready_field(l, "rt_pid"), Some("12"));
        assert_eq!(ready_field(l, "gateway_pid"), Some("13"));
        assert_eq!(ready_field(l, "pid"), None);
    }
}
