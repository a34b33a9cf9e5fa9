//! Drive connection monitoring and the emergency stop (manual: apply in ALL modes).
//!
//! Runs inside the cycle (pure, allocation-free, panic-free). The CANopen master gathers the
//! plain facts per drive ([`DriveStatus`]: heartbeat alive, consecutive missed TPDOs, fault
//! state, pending EMCY code, safe-torque-off input); [`check_drives`] decides which violation
//! they mean, in this order of priority (the root cause first):
//!
//! 1. emergency stop: the global input, or any monitored drive's STO input (statusword bit 14);
//! 2. drive disconnected: heartbeat lost, or `missed_tpdos >= bus.max_missed_tpdos`
//!    (a disconnected drive's fault and EMCY data are stale, so this comes before 3);
//! 3. drive fault: CiA 402 FAULT state, or an EMCY with a non-zero code not yet cleared.
//!
//! Within each step the lowest axis wins. Drives with `monitored == false` (not yet booted or
//! configured) are ignored.
//!
//! ```
//! use mcm_rt_core::safety::{check_drives, Check, DriveInputs, SafetyParams};
//! let p = SafetyParams::from_config(&mcm_shared::config::RobotConfig::prob2_default());
//! let mut inputs = DriveInputs::all_ok();
//! inputs.drives[4].emcy_code = 0x8130; // heartbeat error reported by drive 5
//! inputs.drives[4].fault = true;
//! let v = check_drives(&p, &inputs).unwrap_err();
//! assert_eq!((v.check, v.axis, v.value), (Check::DriveFault, 4, 33072.0));
//! ```

use super::{Check, SafetyParams, Violation};
use mcm_shared::NUM_AXES;

/// What the master knows about one drive this cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DriveStatus {
    /// The drive is expected on the bus (booted and configured); if false it is not checked.
    pub monitored: bool,
    /// The drive's heartbeat arrived within `bus.heartbeat_timeout_ms`.
    pub heartbeat_ok: bool,
    /// Consecutive cycles without the drive's TPDO1.
    pub missed_tpdos: u16,
    /// The drive reports the CiA 402 FAULT (or FAULT REACTION ACTIVE) state.
    pub fault: bool,
    /// Code of the last EMCY received, 0 if none or after an EMCY 0x0000 (error reset).
    pub emcy_code: u16,
    /// Safe torque off / emergency stop input of the drive (statusword bit 14).
    pub sto_active: bool,
}

impl DriveStatus {
    /// A monitored, healthy drive.
    pub const OK: DriveStatus = DriveStatus {
        monitored: true,
        heartbeat_ok: true,
        missed_tpdos: 0,
        fault: false,
        emcy_code: 0,
        sto_active: false,
    };
}

/// Inputs of [`check_drives`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DriveInputs {
    /// The emergency switch is pressed (any source the controller knows of).
    pub emergency_stop: bool,
    /// Per axis (0-based).
    pub drives: [DriveStatus; NUM_AXES],
}

impl DriveInputs {
    /// Six monitored, healthy drives and no emergency stop.
    pub fn all_ok() -> DriveInputs {
        DriveInputs {
            emergency_stop: false,
            drives: [DriveStatus::OK; NUM_AXES],
        }
    }
}

fn violation(check: Check, axis: usize, value: f64, limit: f64) -> Violation {
    Violation {
        check,
        axis,
        value,
        limit,
    }
}

/// The emergency-stop / drive violation these inputs mean, if any (see the module doc for the
/// order). Emergency stop: `axis` = the first monitored drive reporting STO (0 if only the
/// global input is set). Disconnected: `value` = missed TPDOs, `limit` = the maximum.
/// Fault: `value` = the EMCY code (0 if none), `limit` = 0.
pub fn check_drives(params: &SafetyParams, inputs: &DriveInputs) -> Result<(), Violation> {
    let monitored = || {
        inputs
            .drives
            .iter()
            .enumerate()
            .filter(|(_, d)| d.monitored)
    };
    if let Some((axis, _)) = monitored().find(|(_, d)| d.sto_active) {
        return Err(violation(Check::EmergencyStop, axis, 1.0, 0.0));
    }
    if inputs.emergency_stop {
        return Err(violation(Check::EmergencyStop, 0, 1.0, 0.0));
    }
    let max_missed = params.max_missed_tpdos;
    if let Some((axis, d)) =
        monitored().find(|(_, d)| !d.heartbeat_ok || d.missed_tpdos >= max_missed)
    {
        return Err(violation(
            Check::DriveDisconnected,
            axis,
            f64::from(d.missed_tpdos),
            f64::from(max_missed),
        ));
    }
    if let Some((axis, d)) = monitored().find(|(_, d)| d.fault || d.emcy_code != 0) {
        return Err(violation(
            Check::DriveFault,
            axis,
            f64::from(d.emcy_code),
            0.0,
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests;
