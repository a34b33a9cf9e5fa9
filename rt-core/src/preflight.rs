//! Checks at `mcm-rt` start that the configuration alone cannot make: the flight-recorder
//! directory can be written, and the cycle's CPU exists for this process. Runs once before the
//! cycle starts, not inside it.

use mcm_shared::config::RobotConfig;
use std::io::Write;
use std::path::Path;

/// Why `mcm-rt` refuses to start on this machine.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PreflightError {
    #[error(
        "config key `safety.flight_recorder_dir` = {dir} is not usable: {reason}; mcm-rt must be able to create files there (set a writable directory)"
    )]
    FlightRecorderDir { dir: String, reason: String },
    #[error(
        "config key `cycle.cpu` = {cpu} is not allowed: a CPU this process may run on ({available:?}); real-time operation pins the cycle to it"
    )]
    Cpu { cpu: usize, available: Vec<usize> },
}

/// Create `dir` if missing and write (then remove) a probe file in it.
pub fn check_flight_recorder_dir(dir: &str) -> Result<(), PreflightError> {
    let fail = |reason: String| PreflightError::FlightRecorderDir {
        dir: dir.to_string(),
        reason,
    };
    let path = Path::new(dir);
    std::fs::create_dir_all(path).map_err(|e| fail(format!("cannot create it ({e})")))?;
    let probe = path.join(format!(".mcm-rt-probe-{}", std::process::id()));
    let written = std::fs::File::create(&probe).and_then(|mut f| f.write_all(b"probe\n"));
    let _ = std::fs::remove_file(&probe);
    written.map_err(|e| fail(format!("cannot write a file in it ({e})")))
}

/// The CPUs this process may run on.
pub fn available_cpus() -> Vec<usize> {
    core_affinity::get_core_ids()
        .unwrap_or_default()
        .iter()
        .map(|c| c.id)
        .collect()
}

/// Every check; `realtime_required`: `cycle.cpu` must be one of [`available_cpus`] (without
/// real-time scheduling the cycle runs unpinned, and the runner says so).
pub fn check(cfg: &RobotConfig, realtime_required: bool) -> Result<(), PreflightError> {
    check_flight_recorder_dir(&cfg.safety.flight_recorder_dir)?;
    if realtime_required {
        let available = available_cpus();
        if !available.contains(&cfg.cycle.cpu) {
            return Err(PreflightError::Cpu {
                cpu: cfg.cycle.cpu,
                available,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
