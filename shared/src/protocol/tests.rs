use super::*;
use crate::command::{Axis, Direction, PvtChunk, PvtPoint, TorqueControl as TorqueRequest, Which};
use crate::sample::PVT_POINTS_PER_COMMAND;

fn axis(n: u8) -> Axis {
    Axis::new(n).unwrap()
}

fn cfg() -> RobotConfig {
    RobotConfig::prob2_default()
}

fn parse(text: &str) -> Result<Command, CommandError> {
    Command::from_json(text, &cfg())
}

fn points_of(arguments: &serde_json::Value) -> PvtPoints {
    let args = Args::new(&PvtPoints::DEF, Some(arguments)).unwrap();
    PvtPoints::parse(&args, &cfg()).unwrap()
}

fn err(text: &str) -> String {
    parse(text).unwrap_err().to_string()
}

#[test]
fn simple_commands() {
    assert_eq!(parse(r#"{"command":"hold"}"#).unwrap(), Command::Hold(Hold));
    assert_eq!(
        parse(r#"{"command":"status"}"#).unwrap(),
        Command::Status(Status { detail: false })
    );
    assert_eq!(
        parse(r#"{"command":"status","arguments":{"detail":true}}"#).unwrap(),
        Command::Status(Status { detail: true })
    );
    assert_eq!(
        parse(r#"{"command":"info","arguments":{}}"#).unwrap(),
        Command::Info(Info)
    );
}

#[test]
fn unknown_command_suggests() {
    let e = err(r#"{"command":"stauts"}"#);
    assert!(
        e.contains("unknown command \"stauts\"") && e.contains("did you mean \"status\""),
        "{e}"
    );
    let e = err(r#"{"command":"fly"}"#);
    assert!(!e.contains("did you mean"), "{e}");
    assert!(e.contains("known commands: status, info"), "{e}");
}

#[test]
fn structural_errors() {
    assert!(err(r#"{"arguments":{}}"#).contains("needs a \"command\" field"));
    assert!(err(r#"{"command":5}"#).contains("must be a string, got a JSON number"));
    assert!(err(r#"{"command":"hold","argument":{}}"#).contains("unknown field \"argument\""));
    assert!(
        err(r#"{"command":"status","arguments":[1]}"#).contains("\"arguments\" must be an object")
    );
    assert!(err(r#"{"command":"hold","arguments":{"x":1}}"#).contains("takes no arguments"));
}

#[test]
fn move_axis_validation_names_argument_value_and_range() {
    let m = parse(r#"{"command":"move_axis","arguments":{"axis_index":2,"target_position":30}}"#)
        .unwrap();
    assert_eq!(
        m,
        Command::MoveAxis(MoveAxis {
            axis: axis(2),
            target_deg: 30.0,
            velocity_factor: DEFAULT_VELOCITY_FACTOR
        })
    );
    assert_eq!(
        m.requests(),
        [Request::MoveAxis(MoveAxis {
            axis: axis(2),
            target_deg: 30.0,
            velocity_factor: DEFAULT_VELOCITY_FACTOR
        })]
    );
    let e = err(r#"{"command":"move_axis","arguments":{"axis_index":7,"target_position":30}}"#);
    assert_eq!(
        e,
        "move_axis: argument \"axis_index\" = 7 is not allowed; expected an axis number from 1 to 6"
    );
    let e = err(r#"{"command":"move_axis","arguments":{"axis_index":2,"target_position":130}}"#);
    assert!(
        e.contains("\"target_position\" = 130") && e.contains("-119 to 119 deg"),
        "{e}"
    );
    let e = err(r#"{"command":"move_axis","arguments":{"axis_index":2,"target_position":"30"}}"#);
    assert!(e.contains("\"target_position\" = \"30\""), "{e}");
    let e = err(r#"{"command":"move_axis","arguments":{"axis_index":2}}"#);
    assert!(e.contains("missing argument \"target_position\""), "{e}");
    let e = err(
        r#"{"command":"move_axis","arguments":{"axis_index":2,"target_position":3,"velocity_factor":0}}"#,
    );
    assert!(
        e.contains("velocity_factor") && e.contains("from 0.001 to 1"),
        "{e}"
    );
}

#[test]
fn move_all_checks_each_target() {
    let e = err(r#"{"command":"move_all","arguments":{"target_positions":[0,0,0,0,200,0]}}"#);
    assert!(
        e.contains("target_positions[4]") && e.contains("reachable range"),
        "{e}"
    );
    let e = err(r#"{"command":"move_all","arguments":{"target_positions":[0,0,0]}}"#);
    assert!(e.contains("an array of 6"), "{e}");
    let m = parse(r#"{"command":"move_all","arguments":{"target_positions":[1,2,3,4,5,6],"velocity_factor":0.5}}"#).unwrap();
    assert_eq!(
        m.requests(),
        [Request::MoveAll(MoveAll {
            targets_deg: [1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
            velocity_factor: 0.5
        })]
    );
}

#[test]
fn calibrate_arguments() {
    let Command::Calibrate(c) = parse(r#"{"command":"calibrate","arguments":{"which":"wrist","wrist_direction":-1,"force_mechanical_stop":1}}"#).unwrap() else {
        panic!()
    };
    assert_eq!(
        c,
        Calibrate {
            which: Which::Wrist,
            elbow_direction: Direction::Positive,
            wrist_direction: Direction::Negative,
            force_mechanical_stop: true
        }
    );
    let c = parse(r#"{"command":"calibrate","arguments":{"which":3}}"#).unwrap();
    assert_eq!(
        c.requests(),
        [Request::Calibrate(Calibrate {
            which: Which::Axis(axis(3)),
            elbow_direction: Direction::Positive,
            wrist_direction: Direction::Positive,
            force_mechanical_stop: false
        })]
    );
    // Calibrate::default() (what the clients send for "the defaults") is what the MCM reads
    // when no argument is given.
    let c = parse(r#"{"command":"calibrate"}"#).unwrap();
    assert_eq!(c, Command::Calibrate(Calibrate::default()));
    assert!(err(r#"{"command":"calibrate","arguments":{"which":7}}"#).contains("= 7 is not"));
    assert!(
        err(r#"{"command":"calibrate","arguments":{"which":"KNEE"}}"#)
            .contains("\"ALL\", \"ELBOW\"")
    );
    assert!(
        err(r#"{"command":"calibrate","arguments":{"elbow_direction":2}}"#).contains("1 or -1")
    );
}

#[test]
fn pvt_points_batches_are_split() {
    let point = r#"{"position":[0,0,0,0,0,0],"velocity":[0,0,0,0,0,0]}"#;
    let pts = [point; 9].join(",");
    let Command::PvtPoints(p) = parse(&format!(
        r#"{{"command":"pvt_points","arguments":{{"points":[{pts}]}}}}"#
    ))
    .unwrap() else {
        panic!()
    };
    assert_eq!(p.points.len(), 9);
    let requests = Command::PvtPoints(p).requests();
    let chunks: Vec<_> = requests
        .iter()
        .map(|r| match r {
            Request::PvtPoints(c) => (c.points().len(), c.last),
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(PVT_POINTS_PER_COMMAND, 4);
    assert_eq!(chunks, [(4, false), (4, false), (1, true)]);
    assert_eq!(
        requests[2],
        Request::PvtPoints(PvtChunk::new(&[PvtPoint::default()], true).unwrap())
    );
    // A point beyond a limit parses; the core's own check refuses it (`PvtPoints::check`).
    let e = err(
        r#"{"command":"pvt_points","arguments":{"points":[{"position":[0,0,0,0,0,0],"velocity":[0,"fast",0,0,0,0]}]}}"#,
    );
    assert!(e.contains("points[0].velocity[1]"), "{e}");
    assert!(err(r#"{"command":"pvt_points","arguments":{"points":[]}}"#).contains("1 to 1000"));
}

#[test]
fn torque_control_and_sleep() {
    assert_eq!(
        parse(r#"{"command":"torque_control","arguments":{"timeout":0.1,"dt_status":0.01}}"#)
            .unwrap(),
        Command::TorqueControl(TorqueControl {
            request: TorqueRequest {
                timeout_s: Some(0.1),
                gravity_compensation: true
            },
            dt_status: 0.01,
        })
    );
    let t = parse(
        r#"{"command":"torque_control","arguments":{"timeout":-1,"gravity_compensation":false}}"#,
    )
    .unwrap();
    assert_eq!(
        t.requests(),
        [Request::TorqueControl(TorqueRequest {
            timeout_s: None,
            gravity_compensation: false
        })]
    );
    let Command::TorqueControl(t) = parse(r#"{"command":"torque_control"}"#).unwrap() else {
        panic!()
    };
    assert_eq!(t.request.timeout_s, Some(1.0));
    assert!(
        parse(r#"{"command":"sleep","arguments":{"duration":0.5}}"#)
            .unwrap()
            .requests()
            .is_empty()
    );
    assert!(
        err(r#"{"command":"torque_control","arguments":{"timeout":0}}"#).contains("other than 0")
    );
    assert!(err(r#"{"command":"sleep","arguments":{"duration":-1}}"#).contains("0 to 3600"));
    assert!(err(r#"{"command":"sleep"}"#).contains("missing argument \"duration\""));
    assert!(
        err(r#"{"command":"set_torques","arguments":{"torques":[0,0,0,0,0,1e9]}}"#)
            .contains("torques[5]")
    );
}

#[test]
fn sim_fields() {
    let s = parse(r#"{"command":"sim","arguments":{"emergency_stop":true,"block_axis":2,"power_cycle":true}}"#).unwrap();
    assert_eq!(
        s.requests(),
        [Request::Sim(SimCommand {
            emergency_stop: Some(true),
            block_axis: Some(axis(2)),
            power_cycle: true,
            ..SimCommand::default()
        })]
    );
    assert!(
        err(r#"{"command":"sim","arguments":{"unblock_axis":0}}"#)
            .contains("an axis number from 1 to 6")
    );
}

#[test]
fn suggestions() {
    assert_eq!(suggest("stat", command_names()), Some("status"));
    assert_eq!(suggest("mov_all", command_names()), Some("move_all"));
    assert_eq!(suggest("zzzzzz", command_names()), None);
}

#[test]
fn a_pvt_batch_the_core_would_refuse_is_refused_before_sending() {
    use crate::mode::Mode;
    use crate::reply::{PvtQuantity, Reason};
    use crate::sample::StateSample;
    let cfg = RobotConfig::prob2_default();
    let limits = crate::pvt::PointLimits::from_config(&cfg);
    let batch = |n: usize, v0: f64| {
        let p =
            serde_json::json!({"position": [0, 0, 0, 0, 0, 0], "velocity": [v0, 0, 0, 0, 0, 0]});
        points_of(&serde_json::json!({"points": vec![p; n]}))
    };
    let mut state = StateSample {
        mode: Mode::Hold.to_wire(),
        pvt_capacity: 1024,
        ..StateSample::default()
    };
    assert_eq!(
        batch(3, 0.0).check(&limits, &state),
        Err(Reason::WrongMode { mode: Mode::Hold })
    );
    state.mode = Mode::Pvt.to_wire();
    assert_eq!(batch(1000, 0.0).check(&limits, &state), Ok(()));
    state.pvt_queued = 30;
    assert_eq!(
        batch(1000, 0.0).check(&limits, &state),
        Err(Reason::QueueFull {
            offered: 1000,
            free: 994
        })
    );
    // A point at the speed limit passes (the core's limit is the same).
    let max = cfg.axes[0].max_velocity_deg_s;
    assert_eq!(batch(2, max).check(&limits, &state), Ok(()));
    // A position inside the software limits but within the safety margin: the core refuses it.
    let near = cfg.axes[0].max_deg - cfg.safety.limit_margin_deg / 2.0;
    let p = serde_json::json!({"position": [near, 0, 0, 0, 0, 0], "velocity": [0, 0, 0, 0, 0, 0]});
    let b = points_of(&serde_json::json!({"points": [p]}));
    match b.check(&limits, &state) {
        Err(Reason::PvtPoint {
            point: 1,
            quantity: PvtQuantity::Position,
            ..
        }) => {}
        other => panic!("expected a refused point, got {other:?}"),
    }
}

#[test]
fn velocity_control_and_set_velocities() {
    use crate::command::{SetVelocities, VelocityControl as VelocityRequest};
    assert_eq!(
        parse(r#"{"command":"velocity_control","arguments":{"timeout":0.5,"dt_status":0.01}}"#)
            .unwrap(),
        Command::VelocityControl(VelocityControl {
            request: VelocityRequest {
                timeout_s: Some(0.5)
            },
            dt_status: 0.01,
        })
    );
    let v = parse(r#"{"command":"velocity_control","arguments":{"timeout":-1}}"#).unwrap();
    assert_eq!(
        v.requests(),
        [Request::VelocityControl(VelocityRequest {
            timeout_s: None
        })]
    );
    let Command::VelocityControl(v) = parse(r#"{"command":"velocity_control"}"#).unwrap() else {
        panic!()
    };
    assert_eq!((v.request.timeout_s, v.dt_status), (Some(1.0), 0.0));
    assert!(err(r#"{"command":"velocity_control","arguments":{"timeout":0}}"#).contains("timeout"));
    assert!(
        err(r#"{"command":"velocity_control","arguments":{"gravity_compensation":true}}"#)
            .contains("gravity_compensation")
    );

    let s = parse(r#"{"command":"set_velocities","arguments":{"velocities":[0,0,0,0,0,10.0]}}"#)
        .unwrap();
    assert_eq!(
        s.requests(),
        [Request::SetVelocities(SetVelocities {
            velocities_deg_s: [0.0, 0.0, 0.0, 0.0, 0.0, 10.0]
        })]
    );
    // Each within its axis's maximum velocity: axis 2 90 deg/s, axis 4 150 deg/s.
    let e = err(r#"{"command":"set_velocities","arguments":{"velocities":[0,90.5,0,0,0,0]}}"#);
    assert_eq!(
        e,
        "set_velocities: argument \"velocities[1]\" = 90.5 is not allowed; expected a number \
         from -90 to 90 deg/s (the axis's maximum velocity)"
    );
    assert!(
        parse(
            r#"{"command":"set_velocities","arguments":{"velocities":[-90,90,90,150,-150,150]}}"#
        )
        .is_ok()
    );
    assert!(err(r#"{"command":"set_velocities","arguments":{"velocities":[1,2]}}"#).contains("6"));
}

#[test]
fn set_cartesian_velocity_checks_each_component_and_the_frame() {
    use crate::command::{CartesianFrame, SetCartesianVelocity};
    let s = parse(
        r#"{"command":"set_cartesian_velocity","arguments":{"linear":[0.05,0,-1],"angular":[0,180,-2.5]}}"#,
    )
    .unwrap();
    assert_eq!(
        s.requests(),
        [Request::SetCartesianVelocity(SetCartesianVelocity {
            linear_m_s: [0.05, 0.0, -1.0],
            angular_deg_s: [0.0, 180.0, -2.5],
            frame: CartesianFrame::Base,
        })],
        "the base frame by default, the bounds included"
    );
    let t = parse(
        r#"{"command":"set_cartesian_velocity","arguments":{"linear":[0,0,0.02],"angular":[0,0,0],"frame":"tool"}}"#,
    )
    .unwrap();
    assert!(matches!(
        t.requests()[..],
        [Request::SetCartesianVelocity(SetCartesianVelocity {
            frame: CartesianFrame::Tool,
            ..
        })]
    ));
    let e = err(
        r#"{"command":"set_cartesian_velocity","arguments":{"linear":[0,1.5,0],"angular":[0,0,0]}}"#,
    );
    assert_eq!(
        e,
        "set_cartesian_velocity: argument \"linear[1]\" = 1.5 is not allowed; expected a number \
         from -1 to 1 m/s (each component of the TCP's velocity)"
    );
    let e = err(
        r#"{"command":"set_cartesian_velocity","arguments":{"linear":[0,0,0],"angular":[0,0,-181]}}"#,
    );
    assert!(
        e.contains("\"angular[2]\" = -181") && e.contains("-180 to 180 deg/s"),
        "{e}"
    );
    let e = err(
        r#"{"command":"set_cartesian_velocity","arguments":{"linear":[0,0,0],"angular":[0,0,0],"frame":"world"}}"#,
    );
    assert!(
        e.contains("\"frame\"") && e.contains("\"base\" or \"tool\""),
        "{e}"
    );
    let e = err(
        r#"{"command":"set_cartesian_velocity","arguments":{"linear":[0,0],"angular":[0,0,0]}}"#,
    );
    assert!(e.contains("an array of 3 numbers"), "{e}");
    let e = err(r#"{"command":"set_cartesian_velocity","arguments":{"angular":[0,0,0]}}"#);
    assert!(e.contains("missing argument \"linear\""), "{e}");
}

#[test]
fn calibrate_takes_an_axis_number_as_move_axis_does() {
    for which in ["6", "6.0", "\"6\""] {
        let text = format!(r#"{{"command":"calibrate","arguments":{{"which":{which}}}}}"#);
        let Command::Calibrate(c) = parse(&text).unwrap() else {
            panic!("{text}")
        };
        assert_eq!(c.which, Which::Axis(axis(6)), "{text}");
    }
    for which in ["6.5", "0", "7", "\"six\""] {
        let text = format!(r#"{{"command":"calibrate","arguments":{{"which":{which}}}}}"#);
        assert!(err(&text).contains("\"which\""), "{text}");
    }
}

/// Every command a client writes with [`Command::to_json`] reads back as itself: the one
/// encoding of each command serves both directions.
#[test]
fn every_command_reads_back_as_written() {
    use crate::command::SimCommand;
    let p = PvtPoint {
        position_deg: [1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
        velocity_deg_s: [0.5; 6],
    };
    let commands: Vec<Command> = vec![
        Status { detail: false }.into(),
        Status { detail: true }.into(),
        Info.into(),
        Hold.into(),
        Calibrate {
            which: Which::Elbow,
            elbow_direction: Direction::Negative,
            wrist_direction: Direction::Positive,
            force_mechanical_stop: true,
        }
        .into(),
        Calibrate {
            which: Which::Axis(axis(4)),
            elbow_direction: Direction::Positive,
            wrist_direction: Direction::Negative,
            force_mechanical_stop: false,
        }
        .into(),
        Release.into(),
        TorqueControl {
            request: TorqueRequest {
                timeout_s: None,
                gravity_compensation: false,
            },
            dt_status: 0.005,
        }
        .into(),
        SetTorques {
            torques_nm: [1.0, -2.0, 0.5, 0.0, 0.0, 0.25],
        }
        .into(),
        VelocityControl {
            request: crate::command::VelocityControl {
                timeout_s: Some(0.5),
            },
            dt_status: 0.0,
        }
        .into(),
        SetVelocities {
            velocities_deg_s: [0.0, 10.0, -5.0, 0.0, 1.0, 0.0],
        }
        .into(),
        crate::command::SetCartesianVelocity {
            linear_m_s: [0.05, -0.01, 0.0],
            angular_deg_s: [0.0, 2.5, -10.0],
            frame: crate::command::CartesianFrame::Tool,
        }
        .into(),
        crate::command::SetTool {
            tool: crate::tool::Tool::new(
                crate::tool::Tcp {
                    position: [0.0, 0.01, 0.15],
                    orientation: [0.5, 0.5, 0.5, 0.5],
                },
                2.0,
                [0.0, 0.0, 0.06],
                Some([0.01, 0.02, 0.025, 0.001, 0.0, -0.002]),
            )
            .unwrap(),
        }
        .into(),
        crate::command::IdentifyPayload { apply: true }.into(),
        Pvt { dt_s: 0.02 }.into(),
        MoveAxis {
            axis: axis(3),
            target_deg: -45.5,
            velocity_factor: 0.25,
        }
        .into(),
        MoveAll {
            targets_deg: [0.0, 10.0, 20.0, 0.0, -5.0, 0.0],
            velocity_factor: 1.0,
        }
        .into(),
        PvtPoints {
            points: vec![p, PvtPoint::default()],
        }
        .into(),
        Sleep {
            duration: std::time::Duration::from_millis(1500),
        }
        .into(),
        SimCommand::default().into(),
        SimCommand {
            emergency_stop: Some(false),
            disconnect_axis: Some(axis(1)),
            reconnect_axis: Some(axis(2)),
            block_axis: Some(axis(3)),
            unblock_axis: Some(axis(4)),
            external_torques_nm: Some([0.0, 5.0, 0.0, 0.0, 0.0, -1.0]),
            power_cycle: true,
            true_tool: Some(SimCommand::true_tool(2.0, [0.0, 0.0, 0.06]).unwrap()),
        }
        .into(),
        TakeControl.into(),
        ReleaseControl.into(),
        Authenticate {
            secret: Secret("s3cret words".into()),
        }
        .into(),
        MoveToPose {
            pose: Pose {
                position: [0.4, -0.1, 0.5],
                orientation: [0.0, 1.0, 0.0, 0.0],
            },
            velocity_factor: 0.5,
        }
        .into(),
        InverseKinematics {
            pose: Pose {
                position: [0.3, 0.2, 0.25],
                orientation: [0.5, -0.5, 0.5, 0.5],
            },
            seed_deg: Some([0.0, 10.0, 20.0, 0.0, -5.0, 370.0]),
        }
        .into(),
        InverseKinematics {
            pose: Pose {
                position: [0.3, 0.2, 0.25],
                orientation: [0.0, 0.0, 0.0, 1.0],
            },
            seed_deg: None,
        }
        .into(),
        MoveLinear {
            position: [0.4, -0.1, 0.5],
            orientation: Some([0.0, 1.0, 0.0, 0.0]),
            velocity: Some(0.1),
            acceleration: Some(0.5),
        }
        .into(),
        MoveLinear {
            position: [0.4, -0.1, 0.45],
            orientation: None,
            velocity: None,
            acceleration: None,
        }
        .into(),
    ];
    let mut seen = std::collections::BTreeSet::new();
    for c in &commands {
        let text = c.to_json().to_string();
        assert_eq!(&parse(&text).unwrap(), c, "{text}");
        seen.insert(c.name());
    }
    assert_eq!(
        seen.len(),
        COMMANDS.len(),
        "a command is missing from this test"
    );
}

#[test]
fn the_lists_are_derived_from_the_definitions() {
    // Every name is one command's: `find` and the parsing take the first that matches.
    let names: std::collections::BTreeSet<_> =
        command_names().map(str::to_ascii_lowercase).collect();
    assert_eq!(names.len(), COMMANDS.len(), "a command name is used twice");
    let nothing: Vec<_> = COMMANDS
        .iter()
        .filter(|d| d.success == Success::Nothing)
        .map(|d| d.name)
        .collect();
    assert_eq!(
        nothing,
        ["set_torques", "set_velocities", "set_cartesian_velocity"]
    );
    for d in COMMANDS {
        assert_eq!(find(&d.name.to_ascii_uppercase()), Some(*d));
        // Every command of the core has its wire kind, and the kind's name is the command's.
        if let Some(kind) = d.kind {
            assert_eq!(kind.as_str(), d.name);
        }
    }
    // `help` lists each group with its commands: none is empty.
    for g in Group::ALL {
        assert!(
            COMMANDS.iter().any(|c| c.group == g),
            "no command in the help group {g:?} ({})",
            g.title()
        );
    }
    let control: Vec<_> = COMMANDS
        .iter()
        .filter(|d| d.needs_control())
        .map(|d| d.name)
        .collect();
    assert!(
        control.contains(&"move_all") && !control.contains(&"hold"),
        "{control:?}"
    );
}

#[test]
fn axis_arguments_are_refused_under_their_own_names() {
    for (command, name, more) in [
        ("move_axis", "axis_index", r#","target_position":0"#),
        ("sim", "disconnect_axis", ""),
        ("sim", "reconnect_axis", ""),
        ("sim", "block_axis", ""),
        ("sim", "unblock_axis", ""),
    ] {
        let e = err(&format!(
            r#"{{"command":"{command}","arguments":{{"{name}":2.5{more}}}}}"#
        ));
        assert!(
            e.contains(&format!(
                "argument \"{name}\" = 2.5 is not allowed; expected an axis number from 1 to 6"
            )),
            "{e}"
        );
    }
}

/// A missing secret is a missing argument; a secret of the wrong form is refused without
/// echoing it.
#[test]
fn authenticate_says_a_missing_secret_is_missing_and_never_echoes_one() {
    let e = parse(r#"{"command":"authenticate"}"#).unwrap_err();
    assert!(
        matches!(
            e,
            CommandError::Missing {
                command: "authenticate",
                argument: "secret",
                ..
            }
        ),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "authenticate: missing argument \"secret\" (the shared secret as a string of 1 to 1024 \
         bytes)"
    );
    let e = err(r#"{"command":"authenticate","arguments":{"secret":12345678}}"#);
    assert!(
        e.contains("\"secret\" = (not shown)") && !e.contains("12345678"),
        "{e}"
    );
}

/// The default `help` shows for an argument (`ArgDef::default`) is what parsing takes when it
/// is not given (the `DEFAULT_*` constants): given as shown, the command is the same.
#[test]
fn every_default_shown_is_the_default_parsed() {
    use serde_json::{Value, json};
    let zeros = json!([0, 0, 0, 0, 0, 0]);
    let required = |name: &str| match name {
        "authenticate" => json!({"secret": "s"}),
        "move_all" => json!({"target_positions": zeros}),
        "move_axis" => json!({"axis_index": 1, "target_position": 0}),
        "move_linear" => json!({"position": [0.4, 0, 0.5]}),
        "move_to_pose" | "inverse_kinematics" => {
            json!({"position": [0.4, 0, 0.5], "orientation": [0, 0, 0, 1]})
        }
        "pvt_points" => json!({"points": [{"position": zeros, "velocity": zeros}]}),
        "set_torques" => json!({"torques": zeros}),
        "set_velocities" => json!({"velocities": zeros}),
        "set_cartesian_velocity" => json!({"linear": [0, 0, 0], "angular": [0, 0, 0]}),
        "set_tool" => json!({
            "tcp": {"position": [0, 0, 0], "orientation": [0, 0, 0, 1]},
            "mass": 0,
            "center_of_mass": [0, 0, 0]
        }),
        "sleep" => json!({"duration": 0}),
        _ => json!({}),
    };
    let mut checked = Vec::new();
    for d in COMMANDS {
        let base = required(d.name);
        let without =
            Command::parse(d, Some(&base), &cfg()).unwrap_or_else(|e| panic!("{}: {e}", d.name));
        for a in d.args.iter().filter(|a| !a.default.is_empty()) {
            // As written for people: a JSON value, or a word (`ALL`).
            let value: Value =
                serde_json::from_str(a.default).unwrap_or_else(|_| Value::from(a.default));
            let mut with = base.clone();
            with[a.name] = value;
            let given = Command::parse(d, Some(&with), &cfg())
                .unwrap_or_else(|e| panic!("{} {}={}: {e}", d.name, a.name, a.default));
            assert_eq!(given, without, "{}: {} = {}", d.name, a.name, a.default);
            checked.push(format!("{}.{}", d.name, a.name));
        }
    }
    assert_eq!(checked.len(), 18, "{checked:?}");
}

/// `move_linear`'s defaults and ranges are typed as words in its help and in the clients'
/// texts: each must state the values of [`MoveLinear`]'s constants and of the argument table.
#[test]
fn move_linear_texts_state_the_defaults_and_ranges_of_the_contract() {
    use crate::command::MoveLinear;
    use crate::ranges::Arg;
    let (v, a) = (
        MoveLinear::DEFAULT_VELOCITY_M_S,
        MoveLinear::DEFAULT_ACCELERATION_M_S2,
    );
    for (arg, default) in [(Arg::LinearVelocity, v), (Arg::LinearAcceleration, a)] {
        let def = MoveLinear::DEF.args.iter().find(|d| d.name == arg.name());
        let help = def.expect("a move_linear argument").help;
        let (min, max) = arg.fixed_bounds();
        let want = format!("from {min} to {max}; absent: {default}");
        assert!(help.contains(&want), "{help:?} lacks {want:?}");
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let (lv, la) = (Arg::LinearVelocity, Arg::LinearAcceleration);
    for (file, want) in [
        (
            "capi/src/types.rs",
            format!(
                "from {} to {}; 0: the default ({v})",
                lv.fixed_bounds().0,
                lv.fixed_bounds().1
            ),
        ),
        (
            "capi/src/types.rs",
            format!(
                "from {} to {}; 0: the default ({a})",
                la.fixed_bounds().0,
                la.fixed_bounds().1
            ),
        ),
        ("python/src/mcm/tcp.py", format!("(None: {v} and {a})")),
        (
            "docs/clients.md",
            format!("(absent: kept, {v} m/s, {a} m/s²)"),
        ),
    ] {
        let text = std::fs::read_to_string(root.join(file)).expect(file);
        assert!(text.contains(&want), "{file} lacks {want:?}");
    }
}
