use super::*;
use crate::mode::{Mode, RejectCode};
use proptest::prelude::*;

fn axis() -> impl Strategy<Value = Axis> {
    (1u8..=6).prop_map(|n| Axis::new(n).unwrap())
}

fn x() -> impl Strategy<Value = f64> {
    -1e6f64..1e6
}

fn mode() -> impl Strategy<Value = Mode> {
    prop::sample::select(Mode::ALL.to_vec())
}

/// Every reason, with figures.
pub(crate) fn reason() -> impl Strategy<Value = Reason> {
    let cause = prop_oneof![
        x().prop_map(|searched_deg| CalibrationFailure::NoStop { searched_deg }),
        x().prop_map(|searched_deg| CalibrationFailure::NoEdge { searched_deg }),
        Just(CalibrationFailure::DriveLost),
        (x(), x(), x()).prop_map(|(first_deg, second_deg, tolerance_deg)| {
            CalibrationFailure::Inconsistent {
                first_deg,
                second_deg,
                tolerance_deg,
            }
        }),
        (x(), x(), x()).prop_map(|(found_deg, configured_deg, tolerance_deg)| {
            CalibrationFailure::Implausible {
                found_deg,
                configured_deg,
                tolerance_deg,
            }
        }),
        (x(), x())
            .prop_map(|(lag_deg, bound_deg)| CalibrationFailure::Blocked { lag_deg, bound_deg }),
    ];
    let quantity = prop_oneof![
        Just(PvtQuantity::Position),
        Just(PvtQuantity::Velocity),
        Just(PvtQuantity::Acceleration),
    ];
    prop_oneof![
        mode().prop_map(|mode| Reason::WrongMode { mode }),
        axis().prop_map(|axis| Reason::NotCalibrated { axis }),
        Just(Reason::EmergencyStop),
        (axis(), 0u8..64).prop_map(|(axis, also)| Reason::DriveDisconnected { axis, also }),
        (prop::option::of(axis()), any::<u16>())
            .prop_map(|(axis, code)| Reason::DriveFault { axis, code }),
        (prop::option::of(axis()), x(), x(), x()).prop_map(|(axis, value, min, max)| {
            Reason::OutOfRange {
                axis,
                value,
                min,
                max,
            }
        }),
        (
            prop::sample::select(crate::ranges::ARGS.to_vec()),
            prop::option::of(axis()),
            x(),
            x(),
            x()
        )
            .prop_map(|(spec, axis, value, min, max)| {
                Reason::InvalidArgument {
                    refusal: crate::ranges::ArgRefusal {
                        arg: spec.arg,
                        axis,
                        value,
                        min,
                        max,
                    },
                }
            }),
        Just(Reason::NotAvailable),
        Just(Reason::NotSimulated),
        (any::<u32>(), any::<u32>())
            .prop_map(|(offered, free)| Reason::QueueFull { offered, free }),
        (axis(), x(), x()).prop_map(|(axis, a, b)| Reason::PositionLimit {
            axis,
            position_deg: a,
            limit_deg: b
        }),
        (axis(), x(), x()).prop_map(|(axis, a, b)| Reason::VelocityLimit {
            axis,
            velocity_deg_s: a,
            limit_deg_s: b
        }),
        (axis(), x(), x()).prop_map(|(axis, a, b)| Reason::BrakingDistance {
            axis,
            stop_deg: a,
            limit_deg: b
        }),
        (axis(), x(), x()).prop_map(|(axis, a, b)| Reason::FollowingError {
            axis,
            error_deg: a,
            band_deg: b
        }),
        (axis(), x(), x()).prop_map(|(axis, a, b)| Reason::Overload {
            axis,
            current_a: a,
            limit_a: b
        }),
        (axis(), cause).prop_map(|(axis, cause)| Reason::CalibrationFailed { axis, cause }),
        Just(Reason::Aborted),
        x().prop_map(|remaining_s| Reason::Busy { remaining_s }),
        (axis(), any::<u32>(), quantity, x(), x()).prop_map(
            |(axis, point, quantity, value, limit)| Reason::PvtPoint {
                axis,
                point,
                quantity,
                value,
                limit
            }
        ),
        (axis(), x(), x(), x()).prop_map(|(axis, t, a, b)| Reason::Unreachable {
            axis,
            target_deg: t,
            min_deg: a,
            max_deg: b
        }),
        any::<u64>().prop_map(|owner| Reason::NotOwner { owner }),
        (prop::option::of(axis()), line_fault())
            .prop_map(|(axis, fault)| Reason::LineUnreachable { axis, fault }),
        (axis(), line_fault()).prop_map(|(axis, fault)| Reason::LineOutOfRange { axis, fault }),
        Just(Reason::ShuttingDown),
        (x(), x()).prop_map(|(condition, limit)| Reason::NotIdentifiable { condition, limit }),
    ]
}

fn line_fault() -> impl Strategy<Value = LineFault> {
    let singularity = prop_oneof![
        Just(Singularity::Wrist),
        Just(Singularity::Elbow),
        Just(Singularity::Shoulder),
    ];
    prop_oneof![
        x().prop_map(|fraction| LineFault::NoSolution { fraction }),
        (x(), singularity, x(), x()).prop_map(|(fraction, singularity, value, margin)| {
            LineFault::Singular {
                fraction,
                singularity,
                value,
                margin,
            }
        }),
        (x(), x(), x()).prop_map(|(fraction, step_deg, allowed_deg)| LineFault::JointJump {
            fraction,
            step_deg,
            allowed_deg
        }),
        (x(), x(), x()).prop_map(|(fraction, value_deg, limit_deg)| LineFault::OutOfRange {
            fraction,
            value_deg,
            limit_deg
        }),
    ]
}

fn response() -> impl Strategy<Value = Response> {
    let kinds = prop::sample::select(CommandKind::ALL.to_vec());
    let outcome = |kind: CommandKind| -> BoxedStrategy<Outcome> {
        let done = match kind {
            CommandKind::Info => (any::<u32>(), x())
                .prop_map(|(num_axes, period_s)| Done::Info(InfoReply { num_axes, period_s }))
                .boxed(),
            CommandKind::MoveAll => (prop::array::uniform6(x()), axis(), x())
                .prop_map(|(velocities_deg_s, longest, duration_s)| {
                    Done::MoveAll(MoveAllPlan {
                        velocities_deg_s,
                        longest,
                        duration_s,
                    })
                })
                .boxed(),
            CommandKind::IdentifyPayload => (x(), prop::array::uniform3(x()), x())
                .prop_map(|(mass_kg, center_of_mass_m, residual_nm)| {
                    Done::Payload(PayloadReply {
                        mass_kg,
                        center_of_mass_m,
                        residual_nm,
                    })
                })
                .boxed(),
            CommandKind::MoveLinear => (x(), prop::array::uniform6(x()))
                .prop_map(|(duration_s, joint_target_deg)| {
                    Done::MoveLinear(MoveLinearPlan {
                        duration_s,
                        joint_target_deg,
                    })
                })
                .boxed(),
            _ => Just(Done::Ack).boxed(),
        };
        prop_oneof![
            done.prop_map(Outcome::Done),
            reason().prop_map(Outcome::Refused),
            reason().prop_map(Outcome::Failed),
        ]
        .boxed()
    };
    (any::<u64>(), any::<u64>(), kinds).prop_flat_map(move |(client_id, request_id, kind)| {
        outcome(kind).prop_map(move |outcome| Response {
            client_id,
            request_id,
            kind,
            outcome,
        })
    })
}

proptest! {
    #[test]
    fn every_response_round_trips(r in response()) {
        prop_assert_eq!(Response::decode(&r.encode()), Ok(r));
    }

    #[test]
    fn every_safety_error_round_trips(seq in 1u64.., cycle in any::<u64>(), unix_ns in any::<u64>(), reason in reason()) {
        let e = SafetyError { seq, cycle, unix_ns, reason };
        prop_assert_eq!(SafetyError::decode(&e.encode()), Ok(Some(e)));
        prop_assert!(!reason.to_string().is_empty());
    }

    /// Whatever a reply holds, decoding answers without panicking.
    #[test]
    fn any_reply_decodes_or_names_its_fault(
        // 0 (no kind), every known kind (1 up) and the next, unknown one.
        kind in prop_oneof![0u32..=CommandKind::ALL.len() as u32 + 1, any::<u32>()],
        status in prop_oneof![0u32..4, any::<u32>()],
        // Every known code and the next, unknown one.
        code in prop_oneof![0u32..=RejectCode::ALL.len() as u32, any::<u32>()],
        axis in prop_oneof![0u32..8, any::<u32>()],
        values in prop::array::uniform8(prop_oneof![any::<f64>(), (0u8..8).prop_map(f64::from)]),
    ) {
        let r = Reply { kind, status, code, axis, values, ..Reply::default() };
        if let Ok(resp) = Response::decode(&r) {
            prop_assert_eq!(resp.kind.to_wire(), kind);
        }
    }
}

#[test]
fn unknown_codes_are_errors_not_silence() {
    let r = Reply {
        kind: CommandKind::Hold.to_wire(),
        status: ReplyStatus::Rejected.to_wire(),
        code: 200,
        ..Reply::default()
    };
    assert_eq!(
        Response::decode(&r).unwrap_err().to_string(),
        "reject code 200 is not known to this MCM version"
    );
    let none = Reply { code: 0, ..r };
    assert!(Response::decode(&none).is_err(), "a refusal needs a reason");
    assert_eq!(SafetyError::decode(&ErrorRecord::default()), Ok(None));
}

#[test]
fn words_name_the_values() {
    let s = Reason::WrongMode {
        mode: Mode::Release,
    }
    .to_string();
    assert_eq!(s, "not allowed in mode RELEASE");
    let s = Reason::FollowingError {
        axis: Axis::new(3).unwrap(),
        error_deg: 2.5,
        band_deg: 2.0,
    }
    .to_string();
    assert!(
        s.contains("axis 3") && s.contains("2.500") && s.contains("2.000"),
        "{s}"
    );
    let s = Reason::Overload {
        axis: Axis::new(2).unwrap(),
        current_a: 3.9,
        limit_a: 4.0,
    }
    .to_string();
    assert!(
        s.starts_with("overload: axis 2 ")
            && s.contains("derated current of 4.00 A")
            && s.contains("current 3.90 A"),
        "{s}"
    );
    let s = Reason::PvtPoint {
        axis: Axis::new(2).unwrap(),
        point: 5,
        quantity: PvtQuantity::Velocity,
        value: 99.0,
        limit: 90.0,
    }
    .to_string();
    assert_eq!(
        s,
        "point 5: axis 2 velocity 99 deg/s exceeds the limit 90 deg/s; nothing was queued"
    );
}

#[test]
fn undecodable_samples_are_refused_with_their_own_kind_and_ids() {
    let s = CommandSample {
        client_id: 4,
        request_id: 8,
        kind: 99,
        ..CommandSample::default()
    };
    let e = crate::command::Request::decode(&s).unwrap_err();
    let r = refuse_undecodable(&s, &e);
    assert_eq!((r.client_id, r.request_id, r.kind), (4, 8, 99));
    assert_eq!(r.status, ReplyStatus::Rejected.to_wire());
    assert_eq!(r.code, RejectCode::OutOfRange.to_wire());
    assert_eq!(
        &r.values[..3],
        &[
            99.0,
            1.0,
            f64::from(CommandKind::ALL.last().unwrap().to_wire())
        ]
    );

    let mut s = crate::command::Request::Hold.encode();
    s.kind = CommandKind::MoveAll.to_wire();
    s.args[3] = f64::NAN;
    s.args[6] = 0.5;
    let e = crate::command::Request::decode(&s).unwrap_err();
    let r = Response::decode(&refuse_undecodable(&s, &e)).unwrap();
    let Outcome::Refused(Reason::OutOfRange { axis, value, .. }) = r.outcome else {
        panic!("{r:?}")
    };
    assert_eq!(axis, Axis::new(4));
    assert!(value.is_nan());
}

proptest! {
    /// `code()` and `axis()` say what the wire form carries.
    #[test]
    fn code_and_axis_agree_with_the_wire_form(r in reason()) {
        let w = r.to_wire();
        prop_assert_eq!(r.code(), w.code);
        prop_assert_eq!(Axis::to_wire(r.axis()), w.axis);
    }
}

#[test]
fn unknown_figures_of_a_reason_are_named() {
    let unknown =
        |code: RejectCode, values: [f64; 4]| Reason::from_wire(code.to_wire(), 1, &values);
    let cases = [
        (
            RejectCode::CalibrationFailed,
            [9.0, 0.0, 0.0, 0.0],
            "calibration failure",
            9,
        ),
        (
            RejectCode::PvtPoint,
            [1.0, 4.0, 0.0, 0.0],
            "PVT quantity",
            4,
        ),
        (
            RejectCode::DriveFault,
            [70_000.0, 0.0, 0.0, 0.0],
            "drive error code",
            70_000,
        ),
        (
            RejectCode::WrongMode,
            [99.0, 0.0, 0.0, 0.0],
            "operating mode",
            99,
        ),
    ];
    for (code, values, what, value) in cases {
        assert_eq!(
            unknown(code, values),
            Err(DecodeError::Unknown { what, value }),
            "{code:?}"
        );
    }
}

#[test]
fn unknown_and_mismatch_faults_are_refused_as_out_of_range() {
    let s = CommandSample {
        client_id: 2,
        request_id: 3,
        kind: CommandKind::Hold.to_wire(),
        ..CommandSample::default()
    };
    let unknown = DecodeError::Unknown {
        what: "axis",
        value: 9,
    };
    let mismatch = DecodeError::Mismatch {
        kind: CommandKind::Hold,
        problem: "test",
    };
    for (e, value) in [(unknown, 9.0), (mismatch, 0.0)] {
        let r = Response::decode(&refuse_undecodable(&s, &e)).unwrap();
        assert_eq!((r.client_id, r.request_id), (2, 3));
        assert_eq!(
            r.outcome,
            Outcome::Refused(Reason::OutOfRange {
                axis: None,
                value,
                min: 0.0,
                max: 0.0
            }),
            "{e}"
        );
    }
}

#[test]
fn an_undecodable_argument_is_refused_as_the_gateway_words_it() {
    let mut s = crate::command::Request::Hold.encode();
    s.kind = CommandKind::MoveAxis.to_wire();
    s.args[..3].copy_from_slice(&[1.0, 0.0, 1e-320]);
    let e = crate::command::Request::decode(&s).unwrap_err();
    let r = Response::decode(&refuse_undecodable(&s, &e)).unwrap();
    let Outcome::Refused(reason) = r.outcome else {
        panic!("{r:?}")
    };
    assert_eq!(reason.code(), RejectCode::OutOfRange);
    assert_eq!(
        reason
            .argument(CommandKind::MoveAxis)
            .map(|a| a.to_string()),
        Some(
            "argument \"velocity_factor\" = 1e-320 is not allowed; expected a number from \
             0.001 to 1 (a fraction of each axis's maximum velocity)"
                .to_string()
        )
    );
    // An unknown argument code is named, not read as a plain out_of_range.
    assert_eq!(
        Reason::from_wire(RejectCode::OutOfRange.to_wire(), 0, &[1.0, 0.0, 0.0, 99.0]),
        Err(DecodeError::Unknown {
            what: "argument code",
            value: 99
        })
    );
}
