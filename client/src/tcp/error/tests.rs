use super::*;

#[test]
fn refusals_failures_and_unknown_outcomes_are_told_apart_with_their_code() {
    let e = McmError::from_message(
        "move_all",
        "move_all refused: a motion is in progress (0.845 s left); wait until it ends, or send `hold` to stop it",
    );
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Refused, Some(RejectCode::Busy))
    );
    let e = McmError::from_message(
        "calibrate",
        "calibrate failed: calibration of axis 3 failed: no mechanical stop found within 310.0 deg; the arm holds where it is",
    );
    assert_eq!(
        (e.kind, e.code),
        (ErrorKind::Failed, Some(RejectCode::CalibrationFailed))
    );
    let e = McmError::from_message(
        "move_axis",
        "move_axis: no reply from the real-time core within 5 s: the command may or may not have been executed; check the state",
    );
    assert_eq!((e.kind, e.code), (ErrorKind::OutcomeUnknown, None));
    let e = McmError::from_message(
        "move_axis",
        "move_axis: argument \"axis_index\" = 9 is not allowed; expected an axis number from 1 to 6",
    );
    assert_eq!((e.kind, e.code), (ErrorKind::Invalid, None));
    let e = McmError::from_message(
        "move_axis",
        "move_axis refused: the arm is controlled by JSON client 10.1.2.3:51234 (client id 0x1a2b00000003); only `hold`, `status` and `info` are open to others",
    );
    assert_eq!(e.code, Some(RejectCode::NotOwner));
    assert_eq!(e.to_string(), e.message, "the MCM's words, unchanged");
}

#[test]
fn every_reason_of_the_core_is_read_back_to_its_code() {
    use mcm_shared::command::Axis;
    use mcm_shared::mode::Mode;
    use mcm_shared::reply::{CalibrationFailure, PvtQuantity, Reason};
    let a = Axis::new(2).unwrap();
    let reasons = [
        Reason::WrongMode { mode: Mode::Hold },
        Reason::NotCalibrated { axis: a },
        Reason::EmergencyStop,
        Reason::DriveDisconnected { axis: a, also: 0 },
        Reason::DriveDisconnected {
            axis: a,
            also: 0b1_0001,
        },
        Reason::InvalidArgument(mcm_shared::ranges::ArgRefusal {
            arg: mcm_shared::ranges::Arg::VelocityFactor,
            axis: None,
            value: 2.0,
            min: 0.001,
            max: 1.0,
        }),
        Reason::DriveFault {
            axis: Some(a),
            code: 0x2310,
        },
        Reason::OutOfRange {
            axis: None,
            value: 2.0,
            min: 0.0,
            max: 1.0,
        },
        Reason::NotAvailable,
        Reason::NotSimulated,
        Reason::QueueFull {
            offered: 3,
            free: 1,
        },
        Reason::PositionLimit {
            axis: a,
            position_deg: 1.0,
            limit_deg: 0.5,
        },
        Reason::VelocityLimit {
            axis: a,
            velocity_deg_s: 1.0,
            limit_deg_s: 0.5,
        },
        Reason::BrakingDistance {
            axis: a,
            stop_deg: 1.0,
            limit_deg: 0.5,
        },
        Reason::FollowingError {
            axis: a,
            error_deg: 1.0,
            band_deg: 0.5,
        },
        Reason::CalibrationFailed {
            axis: a,
            cause: CalibrationFailure::DriveLost,
        },
        Reason::Aborted,
        Reason::Busy { remaining_s: 1.0 },
        Reason::PvtPoint {
            axis: a,
            point: 2,
            quantity: PvtQuantity::Velocity,
            value: 1.0,
            limit: 0.5,
        },
        Reason::Unreachable {
            axis: a,
            target_deg: 1.0,
            min_deg: 0.0,
            max_deg: 0.5,
        },
        Reason::NotOwner { owner: 7 },
        Reason::ShuttingDown,
    ];
    for r in reasons {
        let e = McmError::from_message("move_axis", &format!("move_axis refused: {r}"));
        assert_eq!(e.code, Some(r.code()), "{r}");
    }
}
