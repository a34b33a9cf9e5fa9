use super::*;

#[test]
fn the_state_is_copied_field_for_field() {
    // Same layout as the sample: every byte of a patterned sample lands at its offset.
    assert_eq!(size_of::<mcm_state_t>(), size_of::<StateSample>());
    assert_eq!(align_of::<mcm_state_t>(), align_of::<StateSample>());
    let mut s = StateSample::default();
    // SAFETY: StateSample is repr(C) of u64/u32/f64 fields without padding (pinned by
    // shared/src/sample.rs's tests), so every byte pattern is a valid value.
    let bytes = unsafe {
        std::slice::from_raw_parts_mut(
            (&mut s as *mut StateSample).cast::<u8>(),
            size_of::<StateSample>(),
        )
    };
    for (i, b) in bytes.iter_mut().enumerate() {
        *b = (i % 251) as u8 + 1;
    }
    let c = mcm_state_t::from(&s);
    // SAFETY: both are plain repr(C) data of the same size.
    let (a, b) = unsafe {
        (
            std::slice::from_raw_parts(
                (&s as *const StateSample).cast::<u8>(),
                size_of::<StateSample>(),
            ),
            std::slice::from_raw_parts(
                (&c as *const mcm_state_t).cast::<u8>(),
                size_of::<mcm_state_t>(),
            ),
        )
    };
    assert_eq!(a, b);
}

#[test]
fn flags_and_modes_are_the_contracts() {
    use mcm_client::mcm_shared::mode::Mode;
    use mcm_client::mcm_shared::sample as c;
    let state = [
        (MCM_STATE_ESTOP, c::STATE_ESTOP),
        (MCM_STATE_SIMULATED, c::STATE_SIMULATED),
        (MCM_STATE_ALL_CALIBRATED, c::STATE_ALL_CALIBRATED),
        (MCM_STATE_PVT_STARVED, c::STATE_PVT_STARVED),
        (MCM_STATE_NOT_REALTIME, c::STATE_NOT_REALTIME),
        (MCM_STATE_SIM_ESTOP, c::STATE_SIM_ESTOP),
        (MCM_STATE_SHUTTING_DOWN, c::STATE_SHUTTING_DOWN),
        (MCM_STATE_CARTESIAN, c::STATE_CARTESIAN),
        (MCM_AXIS_CALIBRATED, c::AXIS_CALIBRATED),
        (MCM_AXIS_ONLINE, c::AXIS_ONLINE),
        (MCM_AXIS_ENABLED, c::AXIS_ENABLED),
        (MCM_AXIS_FAULT, c::AXIS_FAULT),
        (MCM_AXIS_I2T_DERATED, c::AXIS_I2T_DERATED),
    ];
    for (i, (ours, contract)) in state.iter().enumerate() {
        assert_eq!(ours, contract, "flag {i}");
    }
    let modes = [
        (MCM_MODE_OFF, Mode::Off),
        (MCM_MODE_ERROR, Mode::Error),
        (MCM_MODE_HOLD, Mode::Hold),
        (MCM_MODE_RELEASE, Mode::Release),
        (MCM_MODE_TORQUE_CONTROL, Mode::TorqueControl),
        (MCM_MODE_PVT, Mode::Pvt),
        (MCM_MODE_CALIBRATION, Mode::Calibration),
        (MCM_MODE_VELOCITY_CONTROL, Mode::VelocityControl),
    ];
    for (ours, mode) in modes {
        assert_eq!(ours, mode.to_wire(), "{mode:?}");
    }
    assert_eq!(MCM_NUM_AXES, mcm_client::NUM_AXES);
}

#[test]
fn strings_are_cut_to_fit_and_terminated() {
    let mut buf = [1 as c_char; 4];
    fill(&mut buf, "P-Rob2");
    assert_eq!(buf, [b'P' as c_char, b'-' as c_char, b'R' as c_char, 0]);
}

#[test]
fn the_status_carries_the_tcp_once_calibrated() {
    use mcm_client::mcm_shared::sample::{STATE_ALL_CALIBRATED, STATE_CARTESIAN, TcpState};
    let tcp = TcpState {
        position: [0.1, 0.2, 0.9],
        orientation: [0.0, 0.0, 0.6, 0.8],
        linear_velocity: [0.01, 0.0, 0.0],
        angular_velocity: [0.0, 0.0, 5.0],
    };
    let mut s = StateSample {
        cartesian: tcp,
        ..StateSample::default()
    };
    let read = |s: &StateSample| mcm_status_t::from(&Status::from_state(s, false).unwrap());
    let before = read(&s);
    assert!(!before.has_cartesian);
    assert_eq!(before.cartesian, mcm_tcp_state_t::default());
    s.flags = STATE_ALL_CALIBRATED | STATE_CARTESIAN;
    let after = read(&s);
    assert!(after.has_cartesian);
    assert_eq!(after.cartesian, tcp_state(&tcp));
    assert_eq!(after.cartesian.orientation, [0.0, 0.0, 0.6, 0.8]);
}

#[test]
fn the_status_detail_carries_the_active_tool() {
    use mcm_client::mcm_shared::sample::ToolState;
    let tool = ToolState {
        tcp_position: [0.0, 0.0, 0.15],
        tcp_orientation: [0.0, 0.0, 0.6, 0.8],
        mass: 2.0,
        center_of_mass: [0.0, 0.01, 0.06],
        inertia: [0.1, 0.2, 0.3, 0.0, 0.0, 0.0],
    };
    let s = StateSample {
        tool,
        ..StateSample::default()
    };
    let status = Status::from_state(&s, true).unwrap();
    let c = mcm_status_t::from(&status);
    assert!(c.has_detail);
    assert_eq!(c.tool, mcm_state_t::from(&s).tool, "{c:?}");
    let plain = mcm_status_t::from(&Status::from_state(&s, false).unwrap());
    assert_eq!(plain.tool, mcm_tool_t::default(), "no detail, no tool");
}
