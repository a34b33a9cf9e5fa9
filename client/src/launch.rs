//! Start the simulated MCM for a test or a benchmark: the `mcm` launcher of this workspace
//! (real-time core and gateway, simulated robot) with a unique instance name on free loopback
//! ports, stopped on drop. The workspace's end-to-end tests start it through this too
//! (`tests/common`).
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

use mcm_shared::ready::{McmReady, ReadyError, ReadyLine, ZmqEndpoints};
use mcm_shared::service::sim_state_path;
use std::io::{BufRead, BufReader};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

/// Longest wait for the launcher to exit after SIGTERM before it is killed.
const STOP_WAIT: Duration = Duration::from_secs(20);

/// Why the simulated MCM did not start, did not print a line waited for, or did not stop.
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
    #[error("{binary} closed its output before the line waited for (it stopped; see its log)")]
    Exited { binary: PathBuf },
    #[error("the ready line of {binary} cannot be read: {source}")]
    ReadyLine {
        binary: PathBuf,
        #[source]
        source: ReadyError,
    },
    #[error("no line starting with {prefix:?} from {binary} within {waited:?}")]
    NoLine {
        binary: PathBuf,
        prefix: String,
        waited: Duration,
    },
    #[error("{binary} (instance {instance}) did not stop within {waited:?} of SIGTERM; killed")]
    DidNotStop {
        binary: PathBuf,
        instance: String,
        waited: Duration,
    },
}

/// A running simulated MCM; dropping it stops it (SIGTERM, at most 20 s, then SIGKILL) and
/// removes the simulation state its core saved for a restart of this one-off instance
/// ([`SimulatedMcm::stop`] keeps it).
pub struct SimulatedMcm {
    child: Child,
    binary: PathBuf,
    /// The launcher's stdout lines not read yet.
    lines: mpsc::Receiver<String>,
    /// Stopped by [`SimulatedMcm::stop`]: its simulation state is kept for a restart.
    stopped: bool,
    pub instance: String,
    /// The JSON port.
    pub json: SocketAddr,
    /// The telnet HMI port.
    pub hmi: SocketAddr,
    /// The browser pendant's HTTP port (`None` when `[gateway.web]` is off).
    pub web: Option<SocketAddr>,
    /// The ZeroMQ endpoints, when the launcher was asked for them (`--zmq-router`, ...).
    pub zmq: Option<ZmqEndpoints>,
    pub rt_pid: i32,
    pub gateway_pid: i32,
}

/// The first of the launcher's stdout `lines` that starts with `prefix`, waiting at most
/// `within`; the other lines are skipped.
fn wait_line(
    lines: &mpsc::Receiver<String>,
    binary: &Path,
    prefix: &str,
    within: Duration,
) -> Result<String, LaunchError> {
    let deadline = Instant::now() + within;
    loop {
        match lines.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
            Ok(l) if l.starts_with(prefix) => return Ok(l),
            Ok(_) => {}
            Err(RecvTimeoutError::Timeout) => {
                return Err(LaunchError::NoLine {
                    binary: binary.to_path_buf(),
                    prefix: prefix.to_string(),
                    waited: within,
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

/// The launcher's ready line ([`McmReady`]) among the lines of its stdout `lines`, waiting at
/// most `ready_within`; the other lines are skipped.
fn wait_ready(
    lines: &mpsc::Receiver<String>,
    binary: &Path,
    ready_within: Duration,
) -> Result<McmReady, LaunchError> {
    let line = match wait_line(lines, binary, McmReady::PREFIX, ready_within) {
        Err(LaunchError::NoLine { binary, waited, .. }) => {
            return Err(LaunchError::NotReady { binary, waited });
        }
        other => other?,
    };
    line.parse().map_err(|source| LaunchError::ReadyLine {
        binary: binary.to_path_buf(),
        source,
    })
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
        Self::start_echoing(binary, instance, extra, stderr, ready_within, None)
    }

    /// [`SimulatedMcm::start`], writing each line of the launcher's stdout to stderr after
    /// `echo` (e.g. `"[mcm] "`) when given, so that a test's log shows them.
    pub fn start_echoing(
        binary: &Path,
        instance: &str,
        extra: &[&std::ffi::OsStr],
        stderr: Stdio,
        ready_within: Duration,
        echo: Option<&'static str>,
    ) -> Result<SimulatedMcm, LaunchError> {
        Self::start_command(
            Command::new(binary),
            binary,
            instance,
            extra,
            stderr,
            ready_within,
            echo,
        )
    }

    /// [`SimulatedMcm::start_echoing`] with the launcher run by `command` (which runs `binary`
    /// with the arguments added here), e.g. `ip netns exec NAME binary` to run it in a network
    /// namespace. The command must exec the launcher (its pid is the one signalled).
    pub fn start_command(
        mut command: Command,
        binary: &Path,
        instance: &str,
        extra: &[&std::ffi::OsStr],
        stderr: Stdio,
        ready_within: Duration,
        echo: Option<&'static str>,
    ) -> Result<SimulatedMcm, LaunchError> {
        let mut child = command
            .args(["--instance", instance, "--bind", "127.0.0.1"])
            .args(["--json-port", "0", "--hmi-port", "0", "--http-port", "0"])
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
                if let Some(prefix) = echo {
                    eprintln!("{prefix}{line}");
                }
                let _ = tx.send(line);
            }
        });
        let mut mcm = SimulatedMcm {
            child,
            binary: binary.to_path_buf(),
            lines: rx,
            stopped: false,
            instance: instance.to_string(),
            json: SocketAddr::from(([127, 0, 0, 1], 0)),
            hmi: SocketAddr::from(([127, 0, 0, 1], 0)),
            web: None,
            zmq: None,
            rt_pid: 0,
            gateway_pid: 0,
        };
        // On an error `mcm` is dropped, which stops the launcher.
        mcm.wait_ready(ready_within)?;
        Ok(mcm)
    }

    /// Wait at most `within` for the launcher's next ready line (it prints one again when it
    /// restarted the gateway) and take the addresses and pids from it.
    pub fn wait_ready(&mut self, within: Duration) -> Result<(), LaunchError> {
        let ready = wait_ready(&self.lines, &self.binary, within)?;
        self.json = ready.gateway.json;
        self.hmi = ready.gateway.hmi;
        self.web = ready.gateway.web;
        self.zmq = ready.gateway.zmq;
        // A Linux pid is at most 2^22 (`pid_max`): it fits a `pid_t`.
        self.rt_pid = ready.rt_pid as i32;
        self.gateway_pid = ready.gateway_pid as i32;
        Ok(())
    }

    /// The launcher's next stdout line that starts with `prefix`, waiting at most `within`
    /// (the lines before it are skipped).
    pub fn wait_line(&self, prefix: &str, within: Duration) -> Result<String, LaunchError> {
        wait_line(&self.lines, &self.binary, prefix, within)
    }

    /// Stop the launcher with SIGTERM (killed when it does not stop within 20 s: an error)
    /// and return its exit status. The simulation state its core saved is kept: the same
    /// instance started again resumes from it.
    pub fn stop(mut self) -> Result<ExitStatus, LaunchError> {
        self.stopped = true;
        self.terminate()
    }

    /// SIGTERM, then wait at most [`STOP_WAIT`]; SIGKILL after it.
    fn terminate(&mut self) -> Result<ExitStatus, LaunchError> {
        if let Ok(Some(status)) = self.child.try_wait() {
            return Ok(status);
        }
        // SAFETY: kill(2) on our own child's pid; no memory is involved.
        unsafe { libc::kill(self.child.id() as i32, libc::SIGTERM) };
        let deadline = Instant::now() + STOP_WAIT;
        loop {
            if let Ok(Some(status)) = self.child.try_wait() {
                return Ok(status);
            }
            if Instant::now() > deadline {
                let _ = self.child.kill();
                let _ = self.child.wait();
                return Err(LaunchError::DidNotStop {
                    binary: self.binary.clone(),
                    instance: self.instance.clone(),
                    waited: STOP_WAIT,
                });
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for SimulatedMcm {
    fn drop(&mut self) {
        if self.stopped {
            return;
        }
        if let Err(e) = self.terminate() {
            eprintln!("{e}");
        }
        let _ = std::fs::remove_file(sim_state_path(&self.instance));
    }
}
