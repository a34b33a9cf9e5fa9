//! Snapshots of the simulated robot across a restart of `mcm-rt`: real drives keep their power
//! (encoder counts, stored calibration) when only the MCM restarts, so the simulated robot is
//! saved to [`state_path`] when the real-time loop stops and resumed from there at the next
//! start (the file is then deleted).
//!
//! Not in the cycle: file I/O, at start-up and after the loop stopped. Warnings go to stderr.
//!
//! ```
//! use mcm_sim::snapshot;
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let path = snapshot::state_path(&format!("doc-{}", std::process::id()));
//! let bus = snapshot::resume_or_power_up(&cfg, &path); // no snapshot: powered up fresh
//! snapshot::save(&bus, &path);
//! let _resumed = snapshot::resume_or_power_up(&cfg, &path);
//! assert!(!path.exists(), "a resumed snapshot is deleted");
//! ```

use crate::SimBus;
use mcm_shared::config::RobotConfig;
use std::path::{Path, PathBuf};

/// Where the simulated robot waits while `mcm-rt` of `instance` restarts (the one path every
/// program uses: [`mcm_shared::service::sim_state_path`]).
pub fn state_path(instance: &str) -> PathBuf {
    mcm_shared::service::sim_state_path(instance)
}

/// The simulated robot: resumed from `state` (which is then deleted) if an earlier run of the
/// same instance saved it, powered up fresh otherwise (also when the file is unreadable).
pub fn resume_or_power_up(cfg: &RobotConfig, state: &Path) -> SimBus {
    let resumed = SimBus::resume(cfg, state);
    if !matches!(resumed, Ok(None)) {
        let _ = std::fs::remove_file(state);
    }
    match resumed {
        Ok(Some(bus)) => bus,
        Ok(None) => SimBus::new(cfg),
        Err(e) => {
            eprintln!("mcm-rt: WARNING: {e}; the simulated drives power up fresh");
            SimBus::new(cfg)
        }
    }
}

/// Save the simulated robot to `state` for the next start; a failure is only warned about
/// (the next start then powers the drives up fresh).
pub fn save(bus: &SimBus, state: &Path) {
    if let Err(e) = bus.save(state) {
        eprintln!(
            "mcm-rt: WARNING: cannot save the simulation to {}: {e}; the next start powers the drives up fresh",
            state.display()
        );
    }
}
