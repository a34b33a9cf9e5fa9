use super::*;
use crate::transport::hmi::jog::{Jogged, TcpDirection, TcpJog};
use mcm_shared::command::{
    Axis, Calibrate, Direction, MoveAll, MoveAxis, PvtPoint, SetTorques, SimCommand, Which,
};
use mcm_shared::protocol::Status;

fn cfg() -> RobotConfig {
    RobotConfig::prob2_default()
}

fn cmd(line: &str) -> Command {
    match parse_line(line, &cfg()) {
        Ok(Line::Command { cmd, json: false }) => cmd,
        other => panic!("{line}: {other:?}"),
    }
}

fn err(line: &str) -> LineError {
    parse_line(line, &cfg()).expect_err(line)
}

#[test]
fn positional_and_named_arguments() {
    let expected = Command::MoveAxis(MoveAxis {
        axis: Axis::new(1).unwrap(),
        target_deg: 30.0,
        velocity_factor: 0.5,
    });
    assert_eq!(cmd("move_axis 1 30 0.5"), expected);
    assert_eq!(cmd("move_axis 1 30 vf=0.5"), expected);
    assert_eq!(
        cmd("move_axis target=30 axis=1 velocity_factor=.5"),
        expected
    );
    assert_eq!(cmd("  MOVE_AXIS  axis_index=1   30  0.5 "), expected);
    let Command::MoveAxis(m) = cmd("move_axis 2 -45") else {
        panic!()
    };
    assert_eq!((m.axis.number(), m.target_deg), (2, -45.0));
    assert_eq!(
        m.velocity_factor,
        mcm_shared::protocol::DEFAULT_VELOCITY_FACTOR
    );
}

#[test]
fn six_values_as_words_commas_or_json() {
    let expected = Command::MoveAll(MoveAll {
        targets_deg: [0.0, 10.0, 20.0, 0.0, 0.0, 0.0],
        velocity_factor: 0.5,
    });
    assert_eq!(cmd("move_all 0 10 20 0 0 0 vf=0.5"), expected);
    assert_eq!(cmd("move_all 0 10 20 0 0 0 0.5"), expected);
    assert_eq!(cmd("move_all 0,10,20,0,0,0 0.5"), expected);
    assert_eq!(cmd("move_all [0, 10, 20, 0, 0, 0] vf=0.5"), expected);
    assert_eq!(cmd("move_all targets=[0,10,20,0,0,0] vf=0.5"), expected);
    assert_eq!(
        cmd("move_all vf=0.5 target_positions=0,10,20,0,0,0"),
        expected
    );
    assert_eq!(cmd("move_all '[0,10,20,0,0,0]' 0.5"), expected);
    assert_eq!(
        cmd("set_torques 0 0 1.5 0 0 -2"),
        Command::SetTorques(SetTorques {
            torques_nm: [0.0, 0.0, 1.5, 0.0, 0.0, -2.0]
        })
    );
}

#[test]
fn booleans_flags_and_words() {
    assert_eq!(cmd("status"), Command::Status(Status { detail: false }));
    assert_eq!(
        cmd("status detail"),
        Command::Status(Status { detail: true })
    );
    assert_eq!(
        cmd("status detail=true"),
        Command::Status(Status { detail: true })
    );
    assert_eq!(cmd("status true"), Command::Status(Status { detail: true }));
    assert_eq!(
        cmd("status detail=off"),
        Command::Status(Status { detail: false })
    );
    assert_eq!(
        cmd("sim emergency_stop=true"),
        Command::Sim(SimCommand {
            emergency_stop: Some(true),
            ..SimCommand::default()
        })
    );
    let Command::Sim(s) = cmd("sim estop=no block_axis=2 power_cycle torques=0,5,0,0,0,0") else {
        panic!()
    };
    assert_eq!(s.emergency_stop, Some(false));
    assert_eq!(s.block_axis, Axis::new(2));
    assert!(s.power_cycle);
    assert_eq!(s.external_torques_nm, Some([0.0, 5.0, 0.0, 0.0, 0.0, 0.0]));
    let Command::Calibrate(c) = cmd("calibrate which=WRIST") else {
        panic!()
    };
    assert_eq!(c.which, Which::Wrist);
    assert_eq!(
        cmd("calibrate 3 force elbow=-1"),
        Command::Calibrate(Calibrate {
            which: Which::Axis(Axis::new(3).unwrap()),
            elbow_direction: Direction::Negative,
            wrist_direction: Direction::Positive,
            force_mechanical_stop: true
        })
    );
    assert_eq!(cmd("hold"), Command::Hold(mcm_shared::protocol::Hold));
    assert_eq!(cmd("info"), Command::Info(mcm_shared::protocol::Info));
}

#[test]
fn quoted_values() {
    let Command::Calibrate(c) = cmd("calibrate which=\"elbow\"") else {
        panic!()
    };
    assert_eq!(c.which, Which::Elbow);
    let Command::Calibrate(c) = cmd("calibrate 'wrist'") else {
        panic!()
    };
    assert_eq!(c.which, Which::Wrist);
    let t = tokenize(r#"a "two words" 'it''s' "say \"hi\" \\ \n" x='a=b' [1, "]", {"k": [2]}]"#)
        .unwrap();
    let values: Vec<&str> = t.iter().map(|t| t.value.as_str()).collect();
    assert_eq!(
        values,
        [
            "a",
            "two words",
            "its",
            "say \"hi\" \\ \\n",
            "a=b",
            r#"[1, "]", {"k": [2]}]"#
        ]
    );
    assert_eq!(t[4].name.as_deref(), Some("x"));
    assert_eq!(t[4].form, Form::Quoted);
    assert_eq!(t[5].form, Form::Bracketed);
    // A quoted number stays a string: the gateway names the value and the expected type.
    let e = err("move_axis 1 \"30\"").to_string();
    assert!(
        e.contains("\"target_position\" = \"30\"") && e.contains("a number"),
        "{e}"
    );
}

#[test]
fn pvt_points_as_bracketed_or_quoted_json() {
    let point = PvtPoint {
        position_deg: [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        velocity_deg_s: [0.0; 6],
    };
    let json = r#"[{"position": [1, 0, 0, 0, 0, 0], "velocity": [0,0,0,0,0,0]}, {"position":[1,0,0,0,0,0],"velocity":[0,0,0,0,0,0]}]"#;
    for line in [
        format!("pvt_points {json}"),
        format!("pvt_points '{json}'"),
        format!("pvt_points points={json}"),
    ] {
        let Command::PvtPoints(p) = cmd(&line) else {
            panic!()
        };
        assert_eq!(p.points, [point, point], "{line}");
    }
    let e = err("pvt_points [{\"position\" [1,2]}]").to_string();
    assert!(
        e.starts_with("pvt_points: argument \"points\" is not valid JSON"),
        "{e}"
    );
}

#[test]
fn set_tool_takes_its_objects_and_arrays_as_json() {
    for line in [
        r#"set_tool tcp={"position":[0,0,0.15],"orientation":[0,0,0,1]} mass=2 com=[0,0,0.06]"#,
        r#"set_tool tcp='{"position":[0,0,0.15],"orientation":[0,0,0,1]}' mass=2 center_of_mass='[0,0,0.06]'"#,
    ] {
        let Command::SetTool(t) = cmd(line) else {
            panic!("{line}")
        };
        assert_eq!(t.tool.tcp.position, [0.0, 0.0, 0.15], "{line}");
        assert_eq!(
            (t.tool.mass, t.tool.center_of_mass),
            (2.0, [0.0, 0.0, 0.06])
        );
    }
}

#[test]
fn json_lines() {
    assert_eq!(
        parse_line(
            r#"  {"command":"status","arguments":{"detail":true}} "#,
            &cfg()
        )
        .unwrap(),
        Line::Command {
            cmd: Command::Status(Status { detail: true }),
            json: true
        }
    );
    let e = err(r#"{"command":"stauts"}"#);
    assert!(matches!(e, LineError::Json(_)));
    assert!(e.to_string().contains("did you mean \"status\""), "{e}");
}

#[test]
fn session_commands() {
    let p = |l: &str| parse_line(l, &cfg()).unwrap();
    assert_eq!(p(""), Line::Empty);
    assert_eq!(p("   "), Line::Empty);
    assert_eq!(p("help"), Line::Help(None));
    assert_eq!(p("?"), Line::Help(None));
    assert_eq!(p("help move_axis"), Line::Help(Some("move_axis".into())));
    assert_eq!(p("move_axis ?"), Line::Help(Some("move_axis".into())));
    assert_eq!(p("Quit"), Line::Quit);
    assert_eq!(p("exit"), Line::Quit);
    assert_eq!(p("watch"), Line::Watch { detail: false });
    assert_eq!(p("watch detail"), Line::Watch { detail: true });
    assert!(err("watch fast").to_string().contains("watch detail"));
}

#[test]
fn typos_get_suggestions() {
    let e = err("stauts").to_string();
    assert_eq!(
        e,
        "unknown command \"stauts\" (did you mean \"status\"?); type `help` for the list"
    );
    assert!(
        err("mov_axis 1 2")
            .to_string()
            .contains("did you mean \"move_axis\"")
    );
    assert!(err("qiut").to_string().contains("did you mean \"quit\""));
    assert!(!err("fly").to_string().contains("did you mean"));
    let e = err("move_axis 1 30 velocity=0.5").to_string();
    assert!(
        e.contains("unknown argument \"velocity\"")
            && e.contains("did you mean \"velocity_factor\"")
            && e.contains("velocity_factor (vf)"),
        "{e}"
    );
    assert!(err("hold now=1").to_string().contains("takes no arguments"));
}

#[test]
fn wrong_argument_counts_are_explained() {
    let e = err("move_axis 1 2 3 4");
    assert_eq!(
        e.to_string(),
        "move_axis: too many arguments: it takes at most 3 by position (axis_index target_position velocity_factor), got 4"
    );
    assert_eq!(e.command().unwrap().name, "move_axis");
    let e = err("move_axis 1");
    assert!(
        e.to_string()
            .contains("missing argument \"target_position\""),
        "{e}"
    );
    assert_eq!(e.command().unwrap().name, "move_axis");
    let e = err("move_all 1 2 3").to_string();
    assert_eq!(
        e,
        "move_all: \"target_positions\" needs 6 numbers, one per axis, got 3"
    );
    let e = err("move_all 1,2,3").to_string();
    assert!(e.contains("an array of 6"), "{e}");
    assert_eq!(
        err("hold 1").to_string(),
        "hold: too many arguments: it takes no arguments, got 1"
    );
    assert!(
        err("sim 2")
            .to_string()
            .contains("only as name=value, e.g. emergency_stop=")
    );
    let e = err("move_axis 1 30 axis=2").to_string();
    assert_eq!(e, "move_axis: argument \"axis_index\" is given twice");
}

#[test]
fn values_out_of_range_name_value_and_range() {
    let e = err("move_axis 9 0").to_string();
    assert_eq!(
        e,
        "move_axis: argument \"axis_index\" = 9 is not allowed; expected an axis number from 1 to 6"
    );
    let e = err("move_axis 1 500").to_string();
    assert!(e.contains("= 500") && e.contains("-169 to 169"), "{e}");
    let e = err("sim estop=maybe").to_string();
    assert!(e.contains("\"maybe\"") && e.contains("true, false"), "{e}");
}

#[test]
fn syntax_errors() {
    assert_eq!(
        err("calibrate which=\"ALL").to_string(),
        "unterminated \" quote starting at column 17; close it on the same line"
    );
    assert!(matches!(
        err("move_all [0,0,0"),
        LineError::Unbalanced { open: '[', .. }
    ));
    // Columns count characters, not bytes.
    assert!(matches!(
        err("calibrate which=\u{e9}\u{e9}\"x"),
        LineError::UnterminatedQuote { column: 19, .. }
    ));
    assert!(matches!(err("x=1"), LineError::NoCommand { .. }));
    assert!(matches!(err("'status'"), LineError::NoCommand { .. }));
}

#[test]
fn jog_takes_a_direction_of_the_tcp_a_speed_and_a_frame() {
    let tcp = |direction, frame, linear_mm_s, angular_deg_s| {
        Ok(Line::Jog(Jogged::Tcp(TcpJog {
            direction,
            frame,
            linear_mm_s,
            angular_deg_s,
        })))
    };
    let (base, tool) = (CartesianFrame::Base, CartesianFrame::Tool);
    assert_eq!(
        parse_line("jog x", &cfg()),
        tcp(TcpDirection::Along(0), base, 20.0, 10.0)
    );
    assert_eq!(
        parse_line("jog Z 50 tool", &cfg()),
        tcp(TcpDirection::Along(2), tool, 50.0, 10.0)
    );
    assert_eq!(
        parse_line("jog ry tool", &cfg()),
        tcp(TcpDirection::About(1), tool, 20.0, 10.0)
    );
    assert_eq!(
        parse_line("jog rz 30 base", &cfg()),
        tcp(TcpDirection::About(2), base, 20.0, 30.0)
    );
}

#[test]
fn jog_takes_an_axis_and_a_speed() {
    let axis = Axis::new(2).unwrap();
    assert_eq!(
        parse_line("jog 2", &cfg()),
        Ok(Line::Jog(Jogged::Axis { axis, speed: 10.0 }))
    );
    assert_eq!(
        parse_line("jog 2 45.5", &cfg()),
        Ok(Line::Jog(Jogged::Axis { axis, speed: 45.5 }))
    );
    for (line, words) in [
        ("jog", "usage: `jog AXIS [SPEED]`"),
        ("jog 7", "axis = 7"),
        ("jog 2 95", "at most 90 deg/s"),
        ("jog 2 0", "above 0"),
        ("jog 2 fast", "speed = fast is not a number"),
        ("jog 2 10 3", "usage"),
        ("jog w", "axis = w is not allowed"),
        ("jog w", "or a direction of the TCP: x, y, z, rx, ry, rz"),
        ("jog x 1001", "at most 1000 mm/s"),
        ("jog rz 181", "at most 180 deg/s"),
        ("jog y 0", "above 0"),
        ("jog z slow", "speed = slow is not a number"),
        (
            "jog z 10 flange",
            "frame = flange is not allowed; expected base or tool",
        ),
        ("jog z 10 tool 3", "usage"),
    ] {
        let e = err(line).to_string();
        assert!(e.contains(words), "{line}: {e}");
    }
    assert!(cmd("set_velocities 0 10 0 0 0 0") == cmd("set_velocities 0,10,0,0,0,0"));
    assert!(matches!(
        cmd("velocity_control -1"),
        Command::VelocityControl(_)
    ));
}

/// Arguments by position and by short name in one line.
#[test]
fn positions_and_a_short_name_make_one_command() {
    let line = parse_line("move_axis 1 30 vf=0.5", &cfg()).unwrap();
    let expected = MoveAxis {
        axis: Axis::new(1).unwrap(),
        target_deg: 30.0,
        velocity_factor: 0.5,
    };
    assert_eq!(
        line,
        Line::Command {
            cmd: Command::MoveAxis(expected),
            json: false
        }
    );
}

#[test]
fn clear_takes_no_words() {
    assert_eq!(parse_line("clear", &cfg()), Ok(Line::Clear));
    // Nor can `clear / HTTP/1.1` be taken for a session's first line of HTTP.
    assert!(matches!(
        parse_line("clear / HTTP/1.1", &cfg()),
        Err(LineError::Session {
            command: "clear",
            ..
        })
    ));
}

/// A pose is typed as three and four numbers by position, or comma-separated by name.
#[test]
fn a_pose_is_typed_as_three_and_four_numbers() {
    use mcm_shared::protocol::{InverseKinematics, MoveToPose, Pose};
    let pose = Pose {
        position: [0.4, 0.0, 0.5],
        orientation: [0.0, 1.0, 0.0, 0.0],
    };
    let expected = Command::InverseKinematics(InverseKinematics {
        pose,
        seed_deg: None,
    });
    assert_eq!(cmd("inverse_kinematics 0.4 0 0.5 0 1 0 0"), expected);
    assert_eq!(
        cmd("inverse_kinematics pos=0.4,0,0.5 orient=0,1,0,0"),
        expected
    );
    let Command::InverseKinematics(ik) =
        cmd("inverse_kinematics 0.4 0 0.5 0 1 0 0 seed=1,2,3,4,5,6")
    else {
        panic!()
    };
    assert_eq!(ik.seed_deg, Some([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]));
    assert_eq!(
        cmd("move_to_pose 0.4 0 0.5 0 1 0 0 0.5"),
        Command::MoveToPose(MoveToPose {
            pose,
            velocity_factor: 0.5
        })
    );
    assert_eq!(
        err("move_to_pose 0.4 0 0.5 0 1").to_string(),
        "move_to_pose: \"orientation\" needs 4 numbers, a quaternion x, y, z, w, got 2"
    );
    assert_eq!(
        err("inverse_kinematics 0.4 0").to_string(),
        "inverse_kinematics: \"position\" needs 3 numbers, x, y, z in metres, got 2"
    );
}
