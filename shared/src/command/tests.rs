use super::*;
use proptest::prelude::*;

fn axis() -> impl Strategy<Value = Axis> {
    (1u8..=6).prop_map(|n| Axis::new(n).unwrap())
}

fn finite() -> impl Strategy<Value = f64> {
    -1e6f64..1e6
}

fn six() -> impl Strategy<Value = [f64; 6]> {
    prop::array::uniform6(finite())
}

fn factor() -> impl Strategy<Value = f64> {
    prop_oneof![Just(1.0), Just(0.001), (0.001f64..=1.0)]
}

fn direction() -> impl Strategy<Value = Direction> {
    prop_oneof![Just(Direction::Positive), Just(Direction::Negative)]
}

fn which() -> impl Strategy<Value = Which> {
    prop_oneof![
        Just(Which::All),
        Just(Which::Elbow),
        Just(Which::Wrist),
        axis().prop_map(Which::Axis),
    ]
}

fn point() -> impl Strategy<Value = PvtPoint> {
    (six(), six()).prop_map(|(position_deg, velocity_deg_s)| PvtPoint {
        position_deg,
        velocity_deg_s,
    })
}

fn sim() -> impl Strategy<Value = SimCommand> {
    (
        prop::option::of(any::<bool>()),
        prop::array::uniform4(prop::option::of(axis())),
        prop::option::of(prop::array::uniform6(-1000.0f64..=1000.0)),
        any::<bool>(),
        prop::option::of((0.0f64..=5.0, prop::array::uniform3(-0.25f64..0.25))),
    )
        .prop_map(
            |(emergency_stop, axes, external_torques_nm, power_cycle, load)| SimCommand {
                emergency_stop,
                disconnect_axis: axes[0],
                reconnect_axis: axes[1],
                block_axis: axes[2],
                unblock_axis: axes[3],
                external_torques_nm,
                power_cycle,
                true_tool: load.map(|(m, c)| SimCommand::true_tool(m, c).unwrap()),
            },
        )
}

/// Every well-formed request of every kind.
pub(crate) fn request() -> impl Strategy<Value = Request> {
    prop_oneof![
        Just(Request::Status),
        Just(Request::Hold),
        Just(Request::Info),
        Just(Request::Release),
        (which(), direction(), direction(), any::<bool>()).prop_map(|(which, e, w, force)| {
            Request::Calibrate(Calibrate {
                which,
                elbow_direction: e,
                wrist_direction: w,
                force_mechanical_stop: force,
            })
        }),
        (prop::option::of(1e-6f64..=3600.0), any::<bool>()).prop_map(|(timeout_s, g)| {
            Request::TorqueControl(TorqueControl {
                timeout_s,
                gravity_compensation: g,
            })
        }),
        (1e-9f64..=1.0).prop_map(|dt_s| Request::Pvt(Pvt { dt_s })),
        (axis(), finite(), factor()).prop_map(|(axis, target_deg, velocity_factor)| {
            Request::MoveAxis(MoveAxis {
                axis,
                target_deg,
                velocity_factor,
            })
        }),
        (six(), factor()).prop_map(|(targets_deg, velocity_factor)| {
            Request::MoveAll(MoveAll {
                targets_deg,
                velocity_factor,
            })
        }),
        (
            prop::collection::vec(point(), 1..=PVT_POINTS_PER_COMMAND),
            any::<bool>()
        )
            .prop_map(|(p, last)| Request::PvtPoints(PvtChunk::new(&p, last).unwrap())),
        six().prop_map(|torques_nm| Request::SetTorques(SetTorques { torques_nm })),
        sim().prop_map(Request::Sim),
        Just(Request::TakeControl),
        Just(Request::ReleaseControl),
        Just(Request::ClientGone),
        prop::option::of(1e-6f64..=3600.0)
            .prop_map(|timeout_s| Request::VelocityControl(VelocityControl { timeout_s })),
        six().prop_map(|velocities_deg_s| Request::SetVelocities(SetVelocities {
            velocities_deg_s
        })),
        tool().prop_map(|tool| Request::SetTool(SetTool { tool })),
        any::<bool>().prop_map(|apply| Request::IdentifyPayload(IdentifyPayload { apply })),
        (
            prop::array::uniform3(-1.0f64..=1.0),
            prop::array::uniform3(-180.0f64..=180.0),
            prop::sample::select(CartesianFrame::ALL.to_vec()),
        )
            .prop_map(|(linear_m_s, angular_deg_s, frame)| {
                Request::SetCartesianVelocity(SetCartesianVelocity {
                    linear_m_s,
                    angular_deg_s,
                    frame,
                })
            }),
    ]
}

/// A valid tool (orientations whose norm is exactly 1, so that normalising keeps them).
fn tool() -> impl Strategy<Value = crate::tool::Tool> {
    let coordinate = || prop::array::uniform3(-0.25f64..0.25);
    let orientation = prop::sample::select(vec![
        [0.0, 0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0, 0.0],
        [0.5, 0.5, 0.5, 0.5],
        [-0.5, -0.5, 0.5, 0.5],
    ]);
    (
        coordinate(),
        orientation,
        0.0f64..=5.0,
        coordinate(),
        0.0f64..0.1,
    )
        .prop_map(|(position, orientation, mass, center_of_mass, moment)| {
            let tcp = crate::tool::Tcp {
                position,
                orientation,
            };
            let inertia = [moment, moment, moment, 0.0, 0.0, 0.0];
            crate::tool::Tool::new(tcp, mass, center_of_mass, Some(inertia)).unwrap()
        })
}

fn any_sample() -> impl Strategy<Value = CommandSample> {
    let arg = prop_oneof![
        any::<f64>(),
        Just(0.0),
        Just(1.0),
        Just(-1.0),
        (0u8..10).prop_map(f64::from),
        Just(f64::NAN),
        Just(f64::INFINITY),
    ];
    (
        any::<u64>(),
        any::<u64>(),
        prop_oneof![0u32..=CommandKind::ALL.len() as u32 + 1, any::<u32>()],
        prop_oneof![0u32..0x1000, any::<u32>()],
        prop::collection::vec(arg, COMMAND_ARGS),
    )
        .prop_map(|(client_id, request_id, kind, flags, args)| {
            let mut s = CommandSample {
                client_id,
                request_id,
                kind,
                flags,
                ..CommandSample::default()
            };
            s.args.copy_from_slice(&args);
            s
        })
}

proptest! {
    #[test]
    fn every_request_round_trips(r in request(), client in any::<u64>(), id in any::<u64>()) {
        let mut s = r.encode();
        prop_assert_eq!(s.kind, r.kind().to_wire());
        s.client_id = client;
        s.request_id = id;
        prop_assert_eq!(Request::decode(&s), Ok(r));
    }

    /// Whatever a sample holds, decoding answers without panicking, and what it accepts
    /// encodes back to the same request.
    #[test]
    fn any_sample_decodes_or_names_its_fault(s in any_sample()) {
        match Request::decode(&s) {
            Ok(r) => prop_assert_eq!(Request::decode(&r.encode()), Ok(r)),
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }

    #[test]
    fn batches_split_into_full_chunks_and_one_last(n in 1usize..40) {
        let points: Vec<PvtPoint> = (0..n)
            .map(|i| PvtPoint { position_deg: [i as f64; 6], velocity_deg_s: [0.0; 6] })
            .collect();
        let chunks: Vec<PvtChunk> = PvtChunk::batch(&points).collect();
        prop_assert_eq!(chunks.len(), n.div_ceil(PVT_POINTS_PER_COMMAND));
        prop_assert!(chunks.iter().rev().skip(1).all(|c| !c.last));
        prop_assert!(chunks.last().unwrap().last);
        let back: Vec<PvtPoint> = chunks.iter().flat_map(|c| c.points().to_vec()).collect();
        prop_assert_eq!(back, points);
    }
}

fn sample(kind: CommandKind, args: &[f64], flags: u32) -> CommandSample {
    let mut s = CommandSample {
        kind: kind.to_wire(),
        flags,
        ..CommandSample::default()
    };
    s.args[..args.len()].copy_from_slice(args);
    s
}

#[test]
fn bad_values_name_field_value_and_range() {
    let e = Request::decode(&sample(CommandKind::MoveAxis, &[7.0, 30.0, 0.5], 0)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "move_axis: axis_index = 7 is not allowed; allowed: from 1 to 6"
    );
    let e = Request::decode(&sample(CommandKind::MoveAxis, &[1.0, 3.0, 0.0], 0)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "move_axis: velocity_factor = 0 is not allowed; allowed: from 0.001 to 1"
    );
    let e = Request::decode(&sample(CommandKind::MoveAll, &[0.0, 0.0, f64::NAN], 0)).unwrap_err();
    let DecodeError::Invalid { field, .. } = e else {
        panic!("{e:?}")
    };
    assert_eq!(field.to_string(), "target_positions[2]");
    assert_eq!(field.axis(), Axis::new(3));
    let e = Request::decode(&CommandSample {
        kind: 99,
        ..CommandSample::default()
    })
    .unwrap_err();
    assert_eq!(e, DecodeError::UnknownKind(99));
}

#[test]
fn unknown_flag_bits_are_refused() {
    let e = Request::decode(&sample(CommandKind::Hold, &[], 1 << 9)).unwrap_err();
    assert!(e.to_string().contains("flags"), "{e}");
}

#[test]
fn calibrate_sets_and_sim_fields_decode_by_flag() {
    let Request::Calibrate(c) = Request::decode(&sample(
        CommandKind::Calibrate,
        &[8.0, 1.0, -1.0],
        CALIBRATE_FLAG_FORCE_STOP,
    ))
    .unwrap() else {
        panic!()
    };
    assert_eq!(c.which, Which::Wrist);
    assert!(!c.which.contains(Axis::new(3).unwrap()) && c.which.contains(Axis::new(6).unwrap()));
    assert_eq!(c.wrist_direction, Direction::Negative);
    assert!(c.force_mechanical_stop);

    let mut s = sample(
        CommandKind::Sim,
        &[1.0, 0.0, 0.0, 3.0],
        (1 << 0) | (1 << 3) | SIM_FLAG_POWER_CYCLE,
    );
    s.args[5] = f64::NAN; // not flagged: ignored
    let Request::Sim(c) = Request::decode(&s).unwrap() else {
        panic!()
    };
    assert_eq!(c.emergency_stop, Some(true));
    assert_eq!(c.block_axis, Axis::new(3));
    assert_eq!(c.disconnect_axis, None);
    assert_eq!(c.external_torques_nm, None);
    assert!(c.power_cycle);
}

#[test]
fn torque_control_timeout_none_is_negative() {
    let r = Request::TorqueControl(TorqueControl {
        timeout_s: None,
        gravity_compensation: false,
    });
    let s = r.encode();
    assert!(s.args[0] < 0.0);
    assert_eq!(s.flags, TORQUE_FLAG_NO_GRAVITY);
    assert!(Request::decode(&sample(CommandKind::TorqueControl, &[0.0], 0)).is_err());
}

#[test]
fn velocity_control_timeout_and_velocities() {
    let r = Request::VelocityControl(VelocityControl { timeout_s: None });
    assert!(r.encode().args[0] < 0.0);
    assert_eq!(Request::decode(&r.encode()), Ok(r));
    let e = Request::decode(&sample(CommandKind::VelocityControl, &[0.0], 0)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "velocity_control: timeout = 0 is not allowed; allowed: other than 0, at most 3600"
    );
    // The same range as `torque_control`'s timeout.
    let e = Request::decode(&sample(CommandKind::VelocityControl, &[3600.5], 0)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "velocity_control: timeout = 3600.5 is not allowed; allowed: other than 0, at most 3600"
    );
    let e = Request::decode(&sample(CommandKind::VelocityControl, &[1.0], 1)).unwrap_err();
    assert!(e.to_string().contains("flags"), "{e}");
    let e = Request::decode(&sample(
        CommandKind::SetVelocities,
        &[0.0, 0.0, 0.0, f64::INFINITY],
        0,
    ))
    .unwrap_err();
    let DecodeError::Invalid { field, .. } = e else {
        panic!("{e:?}")
    };
    assert_eq!(field.to_string(), "velocities[3]");
    assert_eq!(field.axis(), Axis::new(4));
}

#[test]
fn a_cartesian_velocity_decodes_within_its_ranges_and_frames() {
    let r = Request::SetCartesianVelocity(SetCartesianVelocity {
        linear_m_s: [1.0, -1.0, 0.05],
        angular_deg_s: [180.0, -180.0, 0.0],
        frame: CartesianFrame::Tool,
    });
    assert_eq!(Request::decode(&r.encode()), Ok(r), "the bounds themselves");
    let kind = CommandKind::SetCartesianVelocity;
    let e = Request::decode(&sample(kind, &[0.0, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0], 0)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "set_cartesian_velocity: linear[1] = 1.5 is not allowed; allowed: from -1 to 1"
    );
    let DecodeError::Invalid { field, .. } = e else {
        panic!("{e:?}")
    };
    // A refusal names the element as the gateway's does (`linear[1]`).
    assert_eq!(field.axis(), Axis::new(2));
    let e =
        Request::decode(&sample(kind, &[0.0, 0.0, 0.0, 0.0, 0.0, f64::NAN, 0.0], 0)).unwrap_err();
    assert!(e.to_string().contains("angular[2] = NaN"), "{e}");
    let e = Request::decode(&sample(kind, &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0], 0)).unwrap_err();
    assert!(
        e.to_string().contains("frame = 2") && e.to_string().contains("0 (base) or 1 (tool)"),
        "{e}"
    );
    assert!(
        Request::decode(&sample(kind, &[0.0; 7], 1)).is_err(),
        "no flags"
    );
}

#[test]
fn a_tool_that_is_no_tool_does_not_decode() {
    let mut args = [0.0; 17];
    args[6] = 1.0; // orientation w
    args[7] = 6.0; // mass
    let e = Request::decode(&sample(CommandKind::SetTool, &args, 0)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "set_tool: mass = 6 is not allowed; allowed: from 0 to 5"
    );
    args[7] = 1.0;
    args[6] = 2.0;
    let e = Request::decode(&sample(CommandKind::SetTool, &args, 0)).unwrap_err();
    assert!(
        e.to_string().contains("tcp.orientation = 2 is not allowed"),
        "{e}"
    );
    args[6] = 1.0;
    args[9] = f64::NAN;
    let e = Request::decode(&sample(CommandKind::SetTool, &args, 0)).unwrap_err();
    assert!(e.to_string().contains("center_of_mass[1] = NaN"), "{e}");
}

#[test]
fn pvt_chunk_sizes() {
    assert!(PvtChunk::new(&[], true).is_none());
    assert!(PvtChunk::new(&[PvtPoint::default(); PVT_POINTS_PER_COMMAND + 1], true).is_none());
    assert_eq!(PvtChunk::batch(&[]).count(), 0);
    let e = Request::decode(&sample(CommandKind::PvtPoints, &[], PVT_FLAG_LAST)).unwrap_err();
    assert!(e.to_string().contains("points in the sample"), "{e}");
}

#[test]
fn axes_number_and_index() {
    assert_eq!(Axis::new(0), None);
    assert_eq!(Axis::new(7), None);
    assert_eq!(Axis::from_index(5).unwrap().number(), 6);
    assert_eq!(Axis::new(1).unwrap().index(), 0);
    assert_eq!(Axis::ALL.len(), NUM_AXES);
    assert_eq!(Axis::from_wire(0), Ok(None));
    assert_eq!(Axis::from_wire(9), Err(9));
}

#[test]
fn refusals_of_enumerated_and_bounded_fields_name_them() {
    let cases = [
        (
            sample(CommandKind::Calibrate, &[9.0, 1.0, 1.0], 0),
            "calibrate: which = 9 is not allowed; \
             allowed: 0 (ALL), 1 to 6 (one axis), 7 (ELBOW) or 8 (WRIST)",
        ),
        (
            sample(CommandKind::Calibrate, &[0.0, 0.0, 1.0], 0),
            "calibrate: elbow_direction = 0 is not allowed; allowed: 1 or -1",
        ),
        (
            sample(CommandKind::Pvt, &[f64::INFINITY], 0),
            "pvt: dt = inf is not allowed; allowed: a finite number",
        ),
        (
            sample(CommandKind::TorqueControl, &[0.0], 0),
            "torque_control: timeout = 0 is not allowed; allowed: other than 0, at most 3600",
        ),
        (
            sample(CommandKind::TorqueControl, &[3600.5], 0),
            "torque_control: timeout = 3600.5 is not allowed; allowed: other than 0, at most 3600",
        ),
        (
            sample(CommandKind::Sim, &[2.0], 1),
            "sim: emergency_stop = 2 is not allowed; allowed: 0 (released) or 1 (pressed)",
        ),
    ];
    for (s, text) in cases {
        let e = Request::decode(&s).unwrap_err();
        assert_eq!(e.to_string(), text);
        let DecodeError::Invalid { field, .. } = e else {
            panic!("{e:?}")
        };
        assert_eq!(field.axis(), None, "{text}: not an axis field");
    }
    // dt's range starts at one cycle period: the core checks it, decoding only its finiteness.
    assert!(Request::decode(&sample(CommandKind::Pvt, &[-1.0], 0)).is_ok());
    let e = Request::decode(&sample(
        CommandKind::Sim,
        &[0.0, 0.0, 0.0, 0.0, 0.0, 1001.0],
        1 << 5,
    ))
    .unwrap_err();
    let DecodeError::Invalid { allowed, field, .. } = e else {
        panic!("{e:?}")
    };
    assert_eq!(
        (allowed.bounds(), field.axis()),
        ((-1000.0, 1000.0), Axis::new(1))
    );
    assert_eq!(Allowed::Finite.to_string(), "a finite number");
    assert_eq!(Allowed::Finite.bounds(), (f64::MIN, f64::MAX));
}

#[test]
fn which_covers_its_axes() {
    let covered = |w: Which| -> Vec<u8> {
        (1..=6)
            .filter(|&n| w.contains(Axis::new(n).unwrap()))
            .collect()
    };
    assert_eq!(covered(Which::All), [1, 2, 3, 4, 5, 6]);
    assert_eq!(covered(Which::Elbow), [1, 2, 3]);
    assert_eq!(covered(Which::Wrist), [4, 5, 6]);
    assert_eq!(covered(Which::Axis(Axis::new(5).unwrap())), [5]);
}

#[test]
fn axis_indices_are_zero_based_and_bounded() {
    assert_eq!(Axis::from_index(0), Axis::new(1));
    assert_eq!(Axis::from_index(5), Axis::new(6));
    assert_eq!(Axis::from_index(6), None);
    assert_eq!(Axis::new(6).unwrap().index(), 5);
}

#[test]
fn command_kinds_are_numbered_without_gaps() {
    // `DecodeError::UnknownKind` names the known kinds as a range from the first to the last.
    for (i, k) in CommandKind::ALL.iter().enumerate() {
        assert_eq!(k.to_wire(), i as u32 + 1, "{k}");
    }
    let text = DecodeError::UnknownKind(99).to_string();
    let last = CommandKind::ALL.len();
    assert!(text.ends_with(&format!("(known: 1 to {last})")), "{text}");
}
