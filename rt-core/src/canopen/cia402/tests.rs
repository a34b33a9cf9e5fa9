use super::*;

const ALL: [State; 9] = [
    State::Unknown,
    State::NotReadyToSwitchOn,
    State::SwitchOnDisabled,
    State::ReadyToSwitchOn,
    State::SwitchedOn,
    State::OperationEnabled,
    State::QuickStopActive,
    State::FaultReactionActive,
    State::Fault,
];

#[test]
fn statusword_decodes_by_the_mask_table() {
    assert_eq!(StatusWord(0x0237).state(), State::OperationEnabled);
    assert_eq!(StatusWord(0x0000).state(), State::NotReadyToSwitchOn);
    assert_eq!(StatusWord(0x0040).state(), State::SwitchOnDisabled);
    assert_eq!(StatusWord(0x0021).state(), State::ReadyToSwitchOn);
    assert_eq!(StatusWord(0x0023).state(), State::SwitchedOn);
    assert_eq!(StatusWord(0x0027).state(), State::OperationEnabled);
    assert_eq!(StatusWord(0x0007).state(), State::QuickStopActive);
    assert_eq!(StatusWord(0x000F).state(), State::FaultReactionActive);
    assert_eq!(StatusWord(0x0008).state(), State::Fault);
    assert_eq!(StatusWord(0x0001).state(), State::Unknown);
    // Manufacturer and mode bits do not change the state.
    assert_eq!(StatusWord(0xF637).state(), State::OperationEnabled);
    assert_eq!(StatusWord(0x4250).state(), State::SwitchOnDisabled);
    for s in ALL {
        assert_eq!(statusword_for(s).state(), s, "{s}");
    }
    let sw = StatusWord(0xC000 | 0x2000);
    assert!(sw.emergency_stop() && sw.light_barrier() && sw.following_error());
}

/// Drive a model drive from `start` with one controlword per cycle; return the path.
fn walk(start: State, target: Target, reset: bool, cycles: usize) -> (Vec<State>, Vec<u16>) {
    let mut s = start;
    let mut prev = ControlWord(0);
    let (mut states, mut cws) = (vec![s], vec![]);
    for _ in 0..cycles {
        let cw = next_controlword(s, target, prev, reset);
        s = apply_controlword(s, cw, prev);
        prev = cw;
        states.push(s);
        cws.push(cw.0);
    }
    (states, cws)
}

#[test]
fn every_state_reaches_operation_enabled_one_hop_per_cycle() {
    use State::*;
    let (path, cws) = walk(SwitchOnDisabled, Target::OperationEnabled, false, 4);
    assert_eq!(
        path,
        [
            SwitchOnDisabled,
            ReadyToSwitchOn,
            SwitchedOn,
            OperationEnabled,
            OperationEnabled
        ]
    );
    assert_eq!(cws, [0x06, 0x07, 0x0F, 0x0F]);
    let (path, _) = walk(ReadyToSwitchOn, Target::OperationEnabled, false, 2);
    assert_eq!(path, [ReadyToSwitchOn, SwitchedOn, OperationEnabled]);
    let (path, _) = walk(SwitchedOn, Target::OperationEnabled, false, 1);
    assert_eq!(path, [SwitchedOn, OperationEnabled]);
    let (path, _) = walk(QuickStopActive, Target::OperationEnabled, false, 4);
    assert_eq!(
        path,
        [
            QuickStopActive,
            SwitchOnDisabled,
            ReadyToSwitchOn,
            SwitchedOn,
            OperationEnabled
        ]
    );
    let (path, cws) = walk(Fault, Target::OperationEnabled, true, 5);
    assert_eq!(
        path,
        [
            Fault,
            SwitchOnDisabled,
            ReadyToSwitchOn,
            SwitchedOn,
            OperationEnabled,
            OperationEnabled
        ]
    );
    assert_eq!(cws, [0x80, 0x06, 0x07, 0x0F, 0x0F]);
    // Waiting states hold 0x0000 until the drive moves by itself.
    for s in [Unknown, NotReadyToSwitchOn, FaultReactionActive] {
        assert_eq!(
            next_controlword(s, Target::OperationEnabled, ControlWord(0x0F), true),
            ControlWord(0)
        );
    }
    for s in ALL {
        let (path, _) = walk(s, Target::OperationEnabled, true, 6);
        let ok = matches!(s, Unknown | NotReadyToSwitchOn | FaultReactionActive);
        assert_eq!(
            *path.last().unwrap() == OperationEnabled,
            !ok,
            "from {s}: {path:?}"
        );
    }
}

#[test]
fn fault_reset_is_a_rising_edge_of_bit_7() {
    // Previous controlword had bit 7 set: first drop it, then raise it.
    let cw1 = next_controlword(
        State::Fault,
        Target::OperationEnabled,
        ControlWord(0x80),
        true,
    );
    assert_eq!(cw1, ControlWord(0x00));
    let cw2 = next_controlword(State::Fault, Target::OperationEnabled, cw1, true);
    assert_eq!(cw2, ControlWord(0x80));
    // Fault persists: the edge repeats every two cycles.
    let cw3 = next_controlword(State::Fault, Target::OperationEnabled, cw2, true);
    assert_eq!(cw3, ControlWord(0x00));
    // Without a reset request the fault is held.
    assert_eq!(
        next_controlword(
            State::Fault,
            Target::SwitchOnDisabled,
            ControlWord(0),
            false
        ),
        ControlWord(0)
    );
    // A level without an edge does not reset.
    assert_eq!(
        apply_controlword(State::Fault, ControlWord(0x80), ControlWord(0x80)),
        State::Fault
    );
    assert_eq!(
        apply_controlword(State::Fault, ControlWord(0x80), ControlWord(0x00)),
        State::SwitchOnDisabled
    );
}

#[test]
fn quick_stop_and_disable() {
    use State::*;
    assert_eq!(
        next_controlword(
            OperationEnabled,
            Target::QuickStop,
            ControlWord(0x0F),
            false
        ),
        ControlWord(0x02)
    );
    let (path, _) = walk(OperationEnabled, Target::QuickStop, false, 2);
    assert_eq!(path, [OperationEnabled, QuickStopActive, QuickStopActive]);
    for s in [ReadyToSwitchOn, SwitchedOn] {
        assert_eq!(walk(s, Target::QuickStop, false, 1).0[1], SwitchOnDisabled);
    }
    for s in [
        ReadyToSwitchOn,
        SwitchedOn,
        OperationEnabled,
        QuickStopActive,
    ] {
        let (path, cws) = walk(s, Target::SwitchOnDisabled, false, 1);
        assert_eq!(path[1], SwitchOnDisabled, "from {s}");
        assert_eq!(cws, [0x00]);
    }
}
