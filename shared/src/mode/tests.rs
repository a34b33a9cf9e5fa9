use super::*;

#[test]
fn wire_round_trip() {
    for m in Mode::ALL {
        assert_eq!(Mode::try_from(m.to_wire()), Ok(*m));
    }
    for k in CommandKind::ALL {
        assert_eq!(CommandKind::try_from(k.to_wire()), Ok(*k));
    }
    for c in RejectCode::ALL {
        assert_eq!(RejectCode::try_from(c.to_wire()), Ok(*c));
    }
    assert_eq!(
        Mode::try_from(99).unwrap_err().to_string(),
        "operating mode 99 is not known to this MCM version"
    );
}

#[test]
fn defaults_are_the_zero_wire_values() {
    // A zeroed shared-memory sample must read as "off, nothing rejected".
    assert_eq!(Mode::default(), Mode::Off);
    assert_eq!(Mode::default().to_wire(), 0);
    assert_eq!(RejectCode::default(), RejectCode::None);
    assert_eq!(RejectCode::default().to_wire(), 0);
}

#[test]
fn stops_and_control() {
    let stops: Vec<_> = CommandKind::ALL.iter().filter(|k| k.is_stop()).collect();
    assert_eq!(stops, [&CommandKind::Hold, &CommandKind::ClientGone]);
    assert!(
        CommandKind::may_control(0, 7),
        "nobody owns: the first takes it"
    );
    assert!(CommandKind::may_control(7, 7));
    assert!(!CommandKind::may_control(7, 8));
    assert!(!CommandKind::may_control(0, 0), "client 0 is nobody");
}

#[test]
fn protocol_names() {
    assert_eq!(Mode::TorqueControl.as_str(), "TORQUE_CONTROL");
    assert_eq!(CommandKind::MoveAll.as_str(), "move_all");
    assert_eq!(Mode::VelocityControl.as_str(), "VELOCITY_CONTROL");
    assert_eq!(Mode::VelocityControl.to_wire(), 7);
    assert_eq!(CommandKind::VelocityControl.to_wire(), 16);
    assert_eq!(CommandKind::SetVelocities.as_str(), "set_velocities");
}

#[test]
fn velocity_commands_need_control() {
    assert!(CommandKind::VelocityControl.needs_control());
    assert!(CommandKind::SetVelocities.needs_control());
    assert!(!CommandKind::Hold.needs_control());
}
