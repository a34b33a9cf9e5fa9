use super::*;
use mcm_shared::config::RobotConfig;

fn params() -> SafetyParams {
    SafetyParams::from_config(&RobotConfig::prob2_default())
}

#[test]
fn reject_codes_are_distinct_and_named() {
    let all = [
        Check::PositionLimit,
        Check::VelocityLimit,
        Check::BrakingDistance,
        Check::FollowingError,
        Check::EmergencyStop,
        Check::DriveDisconnected,
        Check::DriveFault,
        Check::NotCalibrated,
    ];
    for (i, a) in all.iter().enumerate() {
        for b in &all[i + 1..] {
            assert_ne!(a.reject_code(), b.reject_code(), "{a:?} {b:?}");
        }
    }
    assert_eq!(
        Check::BrakingDistance.reject_code(),
        RejectCode::BrakingDistance
    );
    assert_eq!(
        Check::NotCalibrated.reject_code(),
        RejectCode::NotCalibrated
    );
}

#[test]
fn violation_message_names_check_axis_value_and_limit() {
    let v = Violation {
        check: Check::FollowingError,
        axis: 2,
        value: 0.05,
        limit: 0.03,
    };
    assert_eq!(
        v.to_string(),
        "safety check following_error tripped on axis 3: value 0.05 rad, limit 0.03 rad"
    );
    let Reason::FollowingError {
        axis,
        error_deg,
        band_deg,
    } = v.reason()
    else {
        panic!("{:?}", v.reason())
    };
    assert_eq!(axis.number(), 3);
    assert!((error_deg - 0.05f64.to_degrees()).abs() < 1e-12);
    assert!((band_deg - 0.03f64.to_degrees()).abs() < 1e-12);
    let f = Violation {
        check: Check::DriveFault,
        axis: 0,
        value: 33088.0,
        limit: 0.0,
    };
    assert_eq!(
        f.reason(),
        Reason::DriveFault {
            axis: Axis::new(1),
            code: 33088
        }
    );
}

#[test]
fn mode_table_follows_the_manual() {
    let hold = ActiveChecks::for_mode(Mode::Hold);
    assert!(hold.drives && hold.following && !hold.limits && !hold.braking);
    let pvt = ActiveChecks::for_mode(Mode::Pvt);
    assert!(pvt.drives && pvt.following && pvt.limits && pvt.braking);
    for m in [Mode::Release, Mode::TorqueControl] {
        let a = ActiveChecks::for_mode(m);
        assert!(a.drives && a.limits && a.braking && !a.following, "{m}");
        assert!(requires_calibration(m));
    }
    for m in [Mode::Off, Mode::Error, Mode::Calibration] {
        let a = ActiveChecks::for_mode(m);
        assert!(a.drives && !a.limits && !a.braking && !a.following, "{m}");
        assert!(!requires_calibration(m));
    }
    assert!(requires_calibration(Mode::Pvt) && !requires_calibration(Mode::Hold));
}

#[test]
fn calibration_check_names_first_uncalibrated_axis() {
    assert_eq!(check_calibrated(&[true; 6]), Ok(()));
    for axis in 0..6 {
        let mut c = [true; 6];
        c[axis] = false;
        let v = check_calibrated(&c).unwrap_err();
        assert_eq!((v.check, v.axis), (Check::NotCalibrated, axis));
    }
}

#[test]
fn check_cycle_runs_only_active_checks_in_order() {
    let p = params();
    let mut q = [0.0; 6];
    q[3] = p.q_max[3] + 0.01; // beyond the limit
    let qd = [0.0; 6];
    let cmd = q;
    let drives = DriveInputs::all_ok();
    let inputs = CycleInputs {
        position: &q,
        velocity: &qd,
        commanded: &cmd,
        drives: &drives,
    };
    // HOLD: limits not checked.
    assert_eq!(
        check_cycle(&p, ActiveChecks::for_mode(Mode::Hold), &inputs),
        Ok(())
    );
    let v = check_cycle(&p, ActiveChecks::for_mode(Mode::Pvt), &inputs).unwrap_err();
    assert_eq!((v.check, v.axis), (Check::PositionLimit, 3));
    // Drives come first.
    let estop = DriveInputs {
        emergency_stop: true,
        ..drives
    };
    let inputs = CycleInputs {
        drives: &estop,
        ..inputs
    };
    let v = check_cycle(&p, ActiveChecks::for_mode(Mode::Pvt), &inputs).unwrap_err();
    assert_eq!(v.check, Check::EmergencyStop);
}

#[test]
fn nan_position_trips_every_mode_that_reads_it() {
    let p = params();
    let mut q = [0.0; 6];
    q[5] = f64::NAN;
    let zero = [0.0; 6];
    let drives = DriveInputs::all_ok();
    let inputs = CycleInputs {
        position: &q,
        velocity: &zero,
        commanded: &zero,
        drives: &drives,
    };
    for m in [Mode::Hold, Mode::Release, Mode::TorqueControl, Mode::Pvt] {
        let v = check_cycle(&p, ActiveChecks::for_mode(m), &inputs).unwrap_err();
        assert_eq!(v.axis, 5, "{m}");
    }
}
