use super::State::*;
use super::*;

fn booted() -> StateMachine {
    let mut sm = StateMachine::new();
    assert_eq!(
        sm.boot_complete(),
        Some((NotReadyToSwitchOn, SwitchOnDisabled))
    );
    sm
}

fn enabled() -> StateMachine {
    let mut sm = booted();
    sm.write_controlword(0x06, true);
    sm.write_controlword(0x0F, true);
    assert_eq!(sm.state(), OperationEnabled);
    sm
}

fn decode(sw: u16) -> State {
    match (sw & 0x4F, sw & 0x6F) {
        (0x00, _) => NotReadyToSwitchOn,
        (0x40, _) => SwitchOnDisabled,
        (0x08, _) => Fault,
        (_, 0x21) => ReadyToSwitchOn,
        (_, 0x23) => SwitchedOn,
        (_, 0x27) => OperationEnabled,
        (_, 0x07) => QuickStopActive,
        _ => panic!("undecodable statusword {sw:04X}"),
    }
}

#[test]
fn enable_walk_and_every_disable_transition() {
    // (controlword from OPERATION ENABLED, expected state): transitions 5, 8, 9, 11
    for (cw, to) in [
        (0x07, SwitchedOn),
        (0x06, ReadyToSwitchOn),
        (0x00, SwitchOnDisabled),
        (0x02, QuickStopActive),
    ] {
        let mut sm = enabled();
        sm.write_controlword(cw, true);
        assert_eq!(sm.state(), to, "cw {cw:04X}");
    }
    let mut sm = booted();
    assert_eq!(
        sm.write_controlword(0x07, true),
        None,
        "switch on needs shutdown first"
    );
    assert_eq!(
        sm.write_controlword(0x06, true),
        Some((SwitchOnDisabled, ReadyToSwitchOn))
    ); // 2
    assert_eq!(
        sm.write_controlword(0x07, true),
        Some((ReadyToSwitchOn, SwitchedOn))
    ); // 3
    assert_eq!(
        sm.write_controlword(0x06, true),
        Some((SwitchedOn, ReadyToSwitchOn))
    ); // 6
    assert_eq!(
        sm.write_controlword(0x00, true),
        Some((ReadyToSwitchOn, SwitchOnDisabled))
    ); // 7
    sm.write_controlword(0x06, true);
    sm.write_controlword(0x07, true);
    assert_eq!(
        sm.write_controlword(0x02, true),
        Some((SwitchedOn, SwitchOnDisabled))
    ); // 10
}

#[test]
fn statusword_encodings_decode_to_the_state() {
    let mut sm = booted();
    let sw = |sm: &StateMachine| sm.statusword(StatusInputs::default());
    assert_eq!(sw(&sm), 0x0250);
    assert_eq!(
        decode(StateMachine::new().statusword(StatusInputs::default())),
        NotReadyToSwitchOn
    );
    for (cw, state, word) in [
        (0x06, ReadyToSwitchOn, 0x0231),
        (0x07, SwitchedOn, 0x0233),
        (0x0F, OperationEnabled, 0x0237),
        (0x02, QuickStopActive, 0x0217),
    ] {
        sm.write_controlword(cw, true);
        assert_eq!((decode(sw(&sm)), sw(&sm)), (state, word));
    }
    sm.fault();
    assert_eq!((decode(sw(&sm)), sw(&sm)), (Fault, 0x0218));
    let inputs = StatusInputs {
        safe_torque_off: true,
        light_barrier: true,
        following: true,
    };
    assert_eq!(
        sm.statusword(inputs),
        0x0008 | 0x0200 | 0x4000 | 0x8000,
        "STO: bit 14 set, bit 4 clear"
    );
    assert_eq!(enabled().statusword(inputs) & 0x1000, 0x1000);
}

#[test]
fn fault_reset_needs_a_rising_edge_of_bit_7() {
    let mut sm = enabled();
    sm.write_controlword(0x80, true); // bit 7 high already before the fault
    assert_eq!(sm.fault(), Some((OperationEnabled, Fault)));
    assert_eq!(sm.fault(), None);
    assert_eq!(sm.write_controlword(0x80, true), None, "held high: no edge");
    assert_eq!(
        sm.write_controlword(0x0F, true),
        None,
        "no level command leaves FAULT"
    );
    assert_eq!(sm.write_controlword(0x00, true), None);
    assert_eq!(
        sm.write_controlword(0x80, true),
        Some((Fault, SwitchOnDisabled))
    ); // 15
    assert_eq!(
        sm.write_controlword(0x86, true),
        None,
        "bit 7 set: not a shutdown command"
    );
    assert_eq!(
        sm.write_controlword(0x06, true),
        Some((SwitchOnDisabled, ReadyToSwitchOn))
    );
}

#[test]
fn quick_stop_ends_in_switch_on_disabled() {
    let mut sm = enabled();
    assert_eq!(
        sm.write_controlword(0x02, true),
        Some((OperationEnabled, QuickStopActive))
    );
    assert_eq!(
        sm.write_controlword(0x0F, true),
        None,
        "no transition 16 with option 2"
    );
    assert_eq!(
        sm.quick_stop_finished(),
        Some((QuickStopActive, SwitchOnDisabled))
    );
    let mut sm = enabled();
    sm.write_controlword(0x02, true);
    assert_eq!(
        sm.write_controlword(0x00, true),
        Some((QuickStopActive, SwitchOnDisabled))
    ); // 12
    assert_eq!(sm.quick_stop_finished(), None);
}

#[test]
fn safe_torque_off_refuses_enabling_and_faults_an_enabled_drive() {
    let mut sm = booted();
    assert_eq!(
        sm.write_controlword(0x06, false),
        None,
        "transition 2 refused"
    );
    assert_eq!(
        sm.reevaluate(true),
        Some((SwitchOnDisabled, ReadyToSwitchOn)),
        "taken once released"
    );
    assert_eq!(
        sm.power_stage_off(),
        Some((ReadyToSwitchOn, SwitchOnDisabled))
    );
    let mut sm = enabled();
    assert_eq!(sm.power_stage_off(), Some((OperationEnabled, Fault)));
    assert!(!sm.state().is_enabled());
}
