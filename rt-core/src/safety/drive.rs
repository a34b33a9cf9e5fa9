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
mod tests {
    use super::*;
    use mcm_shared::config::RobotConfig;

    fn params() -> SafetyParams {
        SafetyParams::from_config(&RobotConfig::prob2_default())
    }

    fn with(axis: usize, edit: impl Fn(&mut DriveStatus)) -> DriveInputs {
        let mut i = DriveInputs::all_ok();
        edit(&mut i.drives[axis]);
        i
    }

    #[test]
    fn healthy_drives_pass() {
        assert_eq!(check_drives(&params(), &DriveInputs::all_ok()), Ok(()));
    }

    #[test]
    fn emergency_stop_global_and_per_drive() {
        let p = params();
        let mut i = DriveInputs::all_ok();
        i.emergency_stop = true;
        assert_eq!(
            check_drives(&p, &i),
            Err(violation(Check::EmergencyStop, 0, 1.0, 0.0))
        );
        for axis in 0..6 {
            let i = with(axis, |d| d.sto_active = true);
            assert_eq!(
                check_drives(&p, &i),
                Err(violation(Check::EmergencyStop, axis, 1.0, 0.0))
            );
        }
    }

    #[test]
    fn missed_tpdos_just_below_and_at_the_maximum_on_each_axis() {
        let p = params();
        let max = p.max_missed_tpdos;
        for axis in 0..6 {
            assert_eq!(
                check_drives(&p, &with(axis, |d| d.missed_tpdos = max - 1)),
                Ok(())
            );
            let e = check_drives(&p, &with(axis, |d| d.missed_tpdos = max)).unwrap_err();
            assert_eq!(
                e,
                violation(
                    Check::DriveDisconnected,
                    axis,
                    f64::from(max),
                    f64::from(max)
                )
            );
            let e = check_drives(&p, &with(axis, |d| d.heartbeat_ok = false)).unwrap_err();
            assert_eq!((e.check, e.axis), (Check::DriveDisconnected, axis));
        }
    }

    #[test]
    fn fault_state_and_emcy_on_each_axis() {
        let p = params();
        for axis in 0..6 {
            let e = check_drives(&p, &with(axis, |d| d.fault = true)).unwrap_err();
            assert_eq!(e, violation(Check::DriveFault, axis, 0.0, 0.0));
            let e = check_drives(&p, &with(axis, |d| d.emcy_code = 0x5441)).unwrap_err();
            assert_eq!(
                e,
                violation(Check::DriveFault, axis, f64::from(0x5441u16), 0.0)
            );
        }
    }

    #[test]
    fn root_cause_first_and_unmonitored_drives_ignored() {
        let p = params();
        // E-stop makes drives fault (EMCY 0x5441): report the e-stop.
        let mut i = with(1, |d| {
            d.fault = true;
            d.emcy_code = 0x5441;
        });
        i.drives[3].sto_active = true;
        assert_eq!(
            check_drives(&p, &i).unwrap_err().check,
            Check::EmergencyStop
        );
        // A silent drive 4 and a faulted drive 1: the disconnection is reported.
        let mut i = with(0, |d| d.fault = true);
        i.drives[3].heartbeat_ok = false;
        let e = check_drives(&p, &i).unwrap_err();
        assert_eq!((e.check, e.axis), (Check::DriveDisconnected, 3));
        // Not yet booted: nothing to report.
        let i = DriveInputs::default();
        assert_eq!(check_drives(&p, &i), Ok(()));
        let i = with(2, |d| {
            *d = DriveStatus {
                monitored: false,
                sto_active: true,
                fault: true,
                ..DriveStatus::default()
            }
        });
        assert_eq!(check_drives(&p, &i), Ok(()));
    }
}
