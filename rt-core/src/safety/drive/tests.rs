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
