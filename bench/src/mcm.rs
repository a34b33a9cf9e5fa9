//! The MCM under test: the `mcm` launcher (mcm-rt + mcm-gateway, simulated robot) started with a
//! unique instance name on free loopback ports ([`SimulatedMcm`] of the client library),
//! stopped with SIGTERM at the end.

use crate::error::BenchError;
use mcm_client::launch::SimulatedMcm;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Longest wait for the launcher's ready line.
const START_WAIT: Duration = Duration::from_secs(60);

/// A running MCM, stopped when dropped.
pub struct Mcm {
    _sim: SimulatedMcm,
    pub json: SocketAddr,
    pub gateway_pid: i32,
    /// Where the launcher's and its children's stderr goes.
    pub log: PathBuf,
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
        Self::start_with(binary, instance, config, &[])
    }

    /// [`Mcm::start`] with more launcher arguments (`more`, e.g. the ZeroMQ endpoints).
    pub fn start_with(
        binary: &Path,
        instance: &str,
        config: Option<&Path>,
        more: &[&str],
    ) -> Result<Mcm, BenchError> {
        let log = std::env::temp_dir().join(format!("mcm-bench-{instance}.log"));
        let log_file = std::fs::File::create(&log)
            .map_err(|e| BenchError::Start(format!("cannot create {}: {e}", log.display())))?;
        let extra: Vec<&std::ffi::OsStr> = config
            .iter()
            .flat_map(|c| [std::ffi::OsStr::new("--config"), c.as_os_str()])
            .chain(more.iter().map(std::ffi::OsStr::new))
            .collect();
        let sim = SimulatedMcm::start(binary, instance, &extra, log_file.into(), START_WAIT)
            .map_err(|e| BenchError::Start(format!("{e}; see {}", log.display())))?;
        Ok(Mcm {
            json: sim.json,
            gateway_pid: sim.gateway_pid,
            _sim: sim,
            log,
        })
    }

    /// Stop with SIGTERM (bounded wait, then SIGKILL) and remove the simulation's saved state
    /// and the log (kept when the run ends any other way, for a look at what went wrong).
    pub fn stop(self) {
        let Mcm { _sim, log, .. } = self;
        drop(_sim);
        let _ = std::fs::remove_file(&log);
    }
}
