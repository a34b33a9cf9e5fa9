use super::*;
use mcm_shared::mode::Mode;

fn params() -> SafetyParams {
    SafetyParams::from_config(&RobotConfig::prob2_default())
}

fn checks() -> CycleChecks {
    CycleChecks::from_config(&RobotConfig::prob2_default())
}

fn in_mode(mode: Mode) -> Situation {
    Situation {
        mode,
        calibrating: Calibrating::No,
        planned_motion: false,
        procedure: false,
        disabled: None,
    }
}

const ALL_MODES: [Mode; 8] = [
    Mode::Off,
    Mode::Error,
    Mode::Calibration,
    Mode::Hold,
    Mode::Pvt,
    Mode::Release,
    Mode::TorqueControl,
    Mode::VelocityControl,
];

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
    let v = Violation {
        check: Check::VelocityLimit,
        axis: 5,
        value: -2.0,
        limit: -1.5,
    };
    assert_eq!(
        v.reason(),
        Reason::VelocityLimit {
            axis: Axis::ALL[5],
            velocity_deg_s: rad_to_deg(-2.0),
            limit_deg_s: rad_to_deg(-1.5),
        }
    );
}

/// Which check runs in which mode: the manual's table (`docs/safety.md`, "Which checks run in
/// which mode").
#[test]
fn mode_table_follows_the_manual() {
    let c = checks();
    for mode in ALL_MODES {
        let now = in_mode(mode);
        let motion = matches!(
            mode,
            Mode::Release | Mode::TorqueControl | Mode::Pvt | Mode::VelocityControl
        );
        let following = matches!(mode, Mode::Hold | Mode::Pvt | Mode::VelocityControl);
        assert_eq!(c.position.runs(&now), motion, "{mode}");
        assert_eq!(c.velocity.runs(&now), motion, "{mode}");
        assert_eq!(c.braking.runs(&now), motion, "{mode}");
        assert_eq!(c.following.runs(&now), following, "{mode}");
        // A planned move or stop was validated when planned: no braking check.
        let planned = Situation {
            planned_motion: true,
            ..now
        };
        assert!(!c.braking.runs(&planned), "{mode}");
        assert_eq!(c.position.runs(&planned), motion, "{mode}");
    }
    // A calibration's searches and its move back to zero: the following error only.
    for calibrating in [Calibrating::Searching, Calibrating::Returning] {
        let now = Situation {
            calibrating,
            ..in_mode(Mode::Calibration)
        };
        assert!(c.following.runs(&now), "{calibrating:?}");
        assert!(!c.position.runs(&now) && !c.velocity.runs(&now) && !c.braking.runs(&now));
    }
    // `identify_payload` in HOLD: its moves are watched as PVT's planned moves, its holds
    // between them as PVT at rest.
    let procedure = Situation {
        procedure: true,
        ..in_mode(Mode::Hold)
    };
    assert!(c.position.runs(&procedure) && c.velocity.runs(&procedure));
    assert!(c.following.runs(&procedure) && c.braking.runs(&procedure));
    let moving = Situation {
        planned_motion: true,
        ..procedure
    };
    assert!(c.position.runs(&moving) && c.velocity.runs(&moving) && !c.braking.runs(&moving));
}

#[test]
fn the_checks_run_in_order_and_the_first_violation_is_reported() {
    let mut c = checks();
    let p = params();
    // Axis 4 beyond its limit moving further out, too fast, its stop beyond the limit, and
    // far from its command: every check would trip.
    let mut q = [0.0; 6];
    q[3] = p.q_max[3] + 0.01;
    let mut qd = [0.0; 6];
    qd[3] = 2.0 * c.velocity.trip[3];
    let cmd = [0.0; 6];
    let inputs = CycleInputs {
        position: &q,
        velocity: &qd,
        commanded: &cmd,
    };
    let pvt = in_mode(Mode::Pvt);
    assert_eq!(
        c.run(&pvt, &inputs).unwrap_err().check,
        Check::PositionLimit
    );
    // Take the causes away one at a time: each next check in the order reports (at rest
    // beyond its limit the axis may move back, so only its following error is left).
    let at_rest = [0.0; 6];
    let mut slower = [0.0; 6];
    slower[3] = c.velocity.trip[3] - 1e-3;
    let mut inside = q;
    inside[3] = p.q_max[3] - p.margin;
    for (position, velocity, check) in [
        (&q, &qd, Check::PositionLimit),
        (&inside, &qd, Check::VelocityLimit),
        (&inside, &slower, Check::BrakingDistance),
        (&q, &at_rest, Check::FollowingError),
    ] {
        let inputs = CycleInputs {
            position,
            velocity,
            commanded: &cmd,
        };
        assert_eq!(c.run(&pvt, &inputs).unwrap_err().check, check);
    }
    // HOLD: only the following error runs.
    let hold = in_mode(Mode::Hold);
    assert_eq!(
        c.run(&hold, &inputs).unwrap_err().check,
        Check::FollowingError
    );
    // OFF and ERROR: none.
    for mode in [Mode::Off, Mode::Error] {
        assert_eq!(c.run(&in_mode(mode), &inputs), Ok(()), "{mode}");
    }
    // The tester's planted bug switches the braking check off, and only that one.
    let inputs = CycleInputs {
        position: &inside,
        velocity: &slower,
        commanded: &inside,
    };
    let planted = Situation {
        disabled: Some(Check::BrakingDistance),
        ..pvt
    };
    assert_eq!(
        c.run(&pvt, &inputs).unwrap_err().check,
        Check::BrakingDistance
    );
    assert_eq!(c.run(&planted, &inputs), Ok(()));
}

#[test]
fn nan_position_trips_every_mode_that_reads_it() {
    let mut c = checks();
    let mut q = [0.0; 6];
    q[5] = f64::NAN;
    let zero = [0.0; 6];
    let inputs = CycleInputs {
        position: &q,
        velocity: &zero,
        commanded: &zero,
    };
    for m in [
        Mode::Hold,
        Mode::Release,
        Mode::TorqueControl,
        Mode::Pvt,
        Mode::VelocityControl,
    ] {
        let v = c.run(&in_mode(m), &inputs).unwrap_err();
        assert_eq!(v.axis, 5, "{m}");
    }
}
