//! Start the simulated MCM for a test or a benchmark: the `mcm` launcher of this workspace
//! (real-time core and gateway, simulated robot) with a unique instance name on free loopback
//! ports, stopped on drop.
//!
//! ```no_run
//! use mcm_client::launch::SimulatedMcm;
//! use std::process::Stdio;
//! use std::time::Duration;
//! let binary = std::path::Path::new("target/debug/mcm");
//! let mcm = SimulatedMcm::start(binary, "my-test-1", &[], Stdio::inherit(), Duration::from_secs(60))?;
//! let mut tcp = mcm_client::tcp::TcpClient::connect(&mcm.json.to_string())?;
//! let mut shm = mcm_client::shm::ShmClient::connect(&mcm.instance)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#[cfg(test)]
mod tests;

use mcm_shared::ready::{McmReady, ReadyError, ReadyLine};
use std::io::{BufRead, BufReader};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

/// Longest wait for the launcher to exit after SIGTERM before it is killed.
const STOP_WAIT: Duration = Duration::from_secs(20);

/// Why the simulated MCM did not start.
#[derive(Debug, thiserror::Error)]
pub enum LaunchError {
    #[error("cannot run {binary}: {source}")]
    Spawn {
        binary: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("no ready line from {binary} within {waited:?}")]
    NotReady { binary: PathBuf, waited: Duration },
    #[error("{binary} closed its output without a ready line (it stopped; see its log)")]
    Exited { binary: PathBuf },
    #[error("the ready line of {binary} cannot be read: {source}")]
    ReadyLine {
        binary: PathBuf,
        #[source]
        source: ReadyError,
    },
}

/// A running simulated MCM; dropping it stops it (SIGTERM, at most 20 s, then SIGKILL) and
/// removes the simulation state its core saved for a restart of this one-off instance.
pub struct SimulatedMcm {
    child: Child,
    pub instance: String,
    /// The JSON port.
    pub json: SocketAddr,
    /// The telnet HMI port.
    pub hmi: SocketAddr,
    pub rt_pid: i32,
    pub gateway_pid: i32,
}

/// The launcher's ready line ([`McmReady`]) among the lines of its stdout `lines`, waiting at
/// most `ready_within`; the other lines are skipped.
fn wait_ready(
    lines: &mpsc::Receiver<String>,
    binary: &Path,
    ready_within: Duration,
) -> Result<McmReady, LaunchError> {
    let deadline = Instant::now() + ready_within;
    loop {
        match lines.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
            Ok(l) if l.starts_with(McmReady::PREFIX) => {
                return l.parse().map_err(|source| LaunchError::ReadyLine {
                    binary: binary.to_path_buf(),
                    source,
                });
            }
            Ok(_) => {}
            Err(RecvTimeoutError::Timeout) => {
                return Err(LaunchError::NotReady {
                    binary: binary.to_path_buf(),
                    waited: ready_within,
                });
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(LaunchError::Exited {
                    binary: binary.to_path_buf(),
                });
            }
        }
    }
}

impl SimulatedMcm {
    /// Run `binary` (the `mcm` launcher) as instance `instance` on free loopback ports, with
    /// `extra` launcher arguments (e.g. `--config FILE`) and `stderr` for its and its
    /// children's log, and wait at most `ready_within` for its ready line.
    pub fn start(
        binary: &Path,
        instance: &str,
        extra: &[&std::ffi::OsStr],
        stderr: Stdio,
        ready_within: Duration,
    ) -> Result<SimulatedMcm, LaunchError> {
        let mut child = Command::new(binary)
            .args(["--instance", instance, "--bind", "127.0.0.1"])
            .args(["--json-port", "0", "--hmi-port", "0"])
            .args(extra)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(stderr)
            .spawn()
            .map_err(|source| LaunchError::Spawn {
                binary: binary.to_path_buf(),
                source,
            })?;
        let stdout = child.stdout.take().expect("stdout is piped");
        let (tx, rx) = mpsc::channel();
        // Reads stdout to its end, so the launcher never blocks on a full pipe.
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                let _ = tx.send(line);
            }
        });
        let mut mcm = SimulatedMcm {
            child,
            instance: instance.to_string(),
            json: SocketAddr::from(([127, 0, 0, 1], 0)),
            hmi: SocketAddr::from(([127, 0, 0, 1], 0)),
            rt_pid: 0,
            gateway_pid: 0,
        };
        // On an error `mcm` is dropped, which stops the launcher.
        let ready = wait_ready(&rx, binary, ready_within)?;
        mcm.json = ready.gateway.json;
        mcm.hmi = ready.gateway.hmi;
        // A Linux pid is at most 2^22 (`pid_max`): it fits a `pid_t`.
        mcm.rt_pid = ready.rt_pid as i32;
        mcm.gateway_pid = ready.gateway_pid as i32;
        Ok(mcm)
    }
}

impl Drop for SimulatedMcm {
    fn drop(&mut self) {
        if self.child.try_wait().ok().flatten().is_none() {
            // SAFETY: kill(2) on our own child's pid; no memory is involved.
            unsafe { libc::kill(self.child.id() as i32, libc::SIGTERM) };
            let deadline = Instant::now() + STOP_WAIT;
            while self.child.try_wait().ok().flatten().is_none() {
                if Instant::now() > deadline {
                    eprintln!(
                        "the simulated MCM {} did not stop within {STOP_WAIT:?}; killing it",
                        self.instance
                    );
                    let _ = self.child.kill();
                    let _ = self.child.wait();
                    break;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
        }
        let saved = std::env::temp_dir().join(format!("mcm-sim-{}.state", self.instance));
        let _ = std::fs::remove_file(saved);
    }
}
