use super::*;
use crate::transport::hmi::words::parse_line;
use mcm_shared::protocol::MoveToPose;
use mcm_shared::sample::ToolState;

fn cfg() -> RobotConfig {
    RobotConfig::prob2_default()
}

fn parse(line: &str) -> Result<Line, LineError> {
    parse_line(line, &cfg())
}

fn close(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12)
}

#[test]
fn moveto_converts_millimetres_and_degrees_into_move_to_pose() {
    let Ok(Line::Command {
        cmd:
            Command::MoveToPose(MoveToPose {
                pose,
                velocity_factor,
            }),
        json: false,
    }) = parse("moveto 400 -50 500 180 0 90 vf=0.3")
    else {
        panic!("{:?}", parse("moveto 400 -50 500 180 0 90 vf=0.3"));
    };
    assert!(close(&pose.position, &[0.4, -0.05, 0.5]), "{pose:?}");
    // Roll 180 then yaw 90 about the fixed axes: the quaternion of Rz(90) Rx(180).
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!(close(&pose.orientation, &[h, h, 0.0, 0.0]), "{pose:?}");
    assert_eq!(velocity_factor, 0.3);
    // The protocol's default velocity factor when none is typed.
    let Ok(Line::Command {
        cmd: Command::MoveToPose(m),
        ..
    }) = parse("moveto 400 0 500 0 0 0")
    else {
        panic!()
    };
    assert_eq!(m.velocity_factor, protocol::DEFAULT_VELOCITY_FACTOR);
}

#[test]
fn movel_converts_millimetres_degrees_and_mm_per_second_into_move_linear() {
    let Ok(Line::Command {
        cmd: Command::MoveLinear(m),
        json: false,
    }) = parse("movel 400 -50 500 180 0 90 v=120")
    else {
        panic!("{:?}", parse("movel 400 -50 500 180 0 90 v=120"));
    };
    assert!(close(&m.position, &[0.4, -0.05, 0.5]), "{m:?}");
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!(close(&m.orientation.unwrap(), &[h, h, 0.0, 0.0]), "{m:?}");
    assert!(close(&[m.velocity.unwrap()], &[0.12]), "{m:?}");
    assert_eq!(m.acceleration, None);
    // Without roll, pitch and yaw the orientation is kept; without a speed the protocol's.
    let Ok(Line::Command {
        cmd: Command::MoveLinear(m),
        ..
    }) = parse("movel 400 0 450")
    else {
        panic!("{:?}", parse("movel 400 0 450"))
    };
    assert_eq!((m.orientation, m.velocity), (None, None));
    assert!(close(&m.position, &[0.4, 0.0, 0.45]), "{m:?}");
    let Ok(Line::Command {
        cmd: Command::MoveLinear(m),
        ..
    }) = parse("movel 400 0 450 speed=1000")
    else {
        panic!()
    };
    assert_eq!(m.velocity, Some(1.0));
}

#[test]
fn movel_refuses_what_it_cannot_move_to_naming_the_value_and_what_is_allowed() {
    for (line, words) in [
        (
            "movel",
            "needs 3 numbers X Y Z or 6 X Y Z ROLL PITCH YAW, got 0",
        ),
        ("movel 400 0 500 180", "got 4"),
        ("movel 400 0 500 180 0 0 0", "got 7"),
        ("movel 400 zero 500", "Y = zero is not a number"),
        ("movel 400 0 500 0 0 nan", "YAW = nan is not a number"),
        ("movel 400 0 500 v=fast", "speed = fast is not a number"),
        (
            "movel 400 0 500 v=2000",
            "speed = 2000 mm/s is not allowed; expected a number from 1 to 1000 mm/s",
        ),
        ("movel 400 0 500 v=0.5", "speed = 0.5 mm/s is not allowed"),
        (
            "movel 400 0 500 vf=0.5",
            "unexpected `0.5` after the numbers",
        ),
    ] {
        let e = parse(line).unwrap_err().to_string();
        assert!(e.contains(words), "{line}: {e}");
        assert!(e.contains("usage: `movel X Y Z"), "{line}: {e}");
    }
}

#[test]
fn moveto_and_tool_refuse_what_is_not_six_numbers_in_words_that_say_so() {
    let e = parse("moveto 400 0 500").unwrap_err().to_string();
    assert!(
        e.contains("needs 6 numbers X Y Z ROLL PITCH YAW, got 3"),
        "{e}"
    );
    let e = parse("moveto 400 0 500 0 zero 0").unwrap_err().to_string();
    assert!(e.contains("PITCH = zero is not a number"), "{e}");
    let e = parse("moveto 400 0 500 0 0 0 speed=2")
        .unwrap_err()
        .to_string();
    assert!(e.contains("unexpected `2` after the numbers"), "{e}");
    // The velocity factor's range is the protocol's, in its words.
    let e = parse("moveto 400 0 500 0 0 0 vf=3").unwrap_err();
    assert!(
        matches!(
            e,
            LineError::Rejected {
                command: "move_to_pose",
                ..
            }
        ),
        "{e:?}"
    );
    let e = parse("tool 0 0 150 0 0 90 com=1,2")
        .unwrap_err()
        .to_string();
    assert!(e.contains("com = 1,2 needs 3 numbers"), "{e}");
    let e = parse("pose now").unwrap_err().to_string();
    assert!(e.contains("pose takes no words"), "{e}");
}

#[test]
fn tool_sets_the_tcp_and_keeps_the_load_unless_one_is_given() {
    assert_eq!(parse("tool"), Ok(Line::Tool(None)));
    let active = Tool::new(
        Tcp::FLANGE,
        3.8,
        [0.0, 0.0, 0.08],
        Some([0.01, 0.01, 0.01, 0.0, 0.0, 0.0]),
    )
    .unwrap();
    let Ok(Line::Tool(Some(edit))) = parse("tool 0 20 150 0 0 90") else {
        panic!()
    };
    let t = edit.tool(&active).unwrap();
    assert!(close(&t.tcp.position, &[0.0, 0.02, 0.15]), "{t:?}");
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!(close(&t.tcp.orientation, &[0.0, 0.0, h, h]), "{t:?}");
    assert_eq!(
        (t.mass, t.center_of_mass, t.inertia),
        (active.mass, active.center_of_mass, active.inertia)
    );

    let Ok(Line::Tool(Some(edit))) = parse("tool 0 0 150 0 0 0 mass=1.5 com=0,0,60") else {
        panic!()
    };
    let t = edit.tool(&active).unwrap();
    assert_eq!(t.mass, 1.5);
    assert!(close(&t.center_of_mass, &[0.0, 0.0, 0.06]), "{t:?}");
    assert_eq!(t.inertia, [0.0; 6], "a point mass");
    let Ok(Line::Tool(Some(edit))) = parse("tool 0 0 150 0 0 0 mass=2") else {
        panic!()
    };
    assert_eq!(
        edit.tool(&active).unwrap().center_of_mass,
        active.center_of_mass
    );

    // The tool's own checks, in metres as set_tool checks them.
    let Ok(Line::Tool(Some(edit))) = parse("tool 0 0 150 0 0 0 mass=9") else {
        panic!()
    };
    let e = edit.tool(&active).unwrap_err().to_string();
    assert!(e.contains("mass"), "{e}");
}

#[test]
fn pose_shows_the_tcp_in_millimetres_and_degrees_and_the_tool() {
    let cfg = cfg();
    let mut s = StateSample::default();
    let none = pose_text(Some(&s), &cfg);
    assert!(
        none.contains("no TCP pose: not every axis is calibrated"),
        "{none}"
    );
    let h = std::f64::consts::FRAC_1_SQRT_2;
    s.flags |= STATE_CARTESIAN;
    s.cartesian.position = [0.4123, -0.05, 0.5];
    // Roll 180 and yaw 90.
    s.cartesian.orientation = [h, h, 0.0, 0.0];
    s.cartesian.linear_velocity = [0.03, 0.04, 0.0];
    s.tool = ToolState::from(
        &Tool::new(
            Tcp {
                position: [0.0, 0.0, 0.15],
                orientation: [0.0, 0.0, h, h],
            },
            1.2,
            [0.0, 0.0, 0.06],
            None,
        )
        .unwrap(),
    );
    let text = pose_text(Some(&s), &cfg);
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(
        rows[3].split_whitespace().collect::<Vec<_>>(),
        ["412.30", "-50.00", "500.00", "180.000", "0.000", "90.000"],
        "{text}"
    );
    assert!(text.contains("speed 50.0 mm/s"), "{text}");
    assert!(
        text.contains("TCP in the flange frame at      0.00      0.00    150.00 mm, roll pitch yaw     0.000     0.000    90.000 deg"),
        "{text}"
    );
    assert!(
        text.contains(
            "load 1.200 kg, centre of mass at      0.00      0.00     60.00 mm, a point mass"
        ),
        "{text}"
    );
    assert!(text.contains("the URDF's rpy"), "{text}");
    assert!(pose_text(None, &cfg).contains("publishes no state"));
}
