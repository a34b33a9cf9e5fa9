//! CiA 402 drive state machine, master side: controlword / statusword newtypes, state decoding
//! by the mask table, and a transition table in the style of ros2_canopen's `Command402`:
//! given the current state and the wanted state, the controlword for the next hop. The master
//! calls [`next_controlword`] once per cycle with the latest statusword, so it walks one hop
//! per cycle (SWITCH ON DISABLED -> READY TO SWITCH ON -> SWITCHED ON -> OPERATION ENABLED).
//!
//! Runs inside the cycle: pure functions over `Copy` values.
//!
//! ```
//! use mcm_rt_core::canopen::cia402::{next_controlword, ControlWord, State, StatusWord, Target};
//! let state = StatusWord(0x0250).state();
//! assert_eq!(state, State::SwitchOnDisabled);
//! let cw = next_controlword(state, Target::OperationEnabled, ControlWord(0), false);
//! assert_eq!(cw, ControlWord::SHUTDOWN);
//! ```

/// Controlword 0x6040.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ControlWord(pub u16);

impl ControlWord {
    /// Transitions 2, 6, 8.
    pub const SHUTDOWN: ControlWord = ControlWord(0x0006);
    /// Transition 3.
    pub const SWITCH_ON: ControlWord = ControlWord(0x0007);
    /// Transitions 4, 16 (also 3+4).
    pub const ENABLE_OPERATION: ControlWord = ControlWord(0x000F);
    /// Transition 5 (same bits as switch on).
    pub const DISABLE_OPERATION: ControlWord = ControlWord(0x0007);
    /// Transitions 7, 9, 10, 12.
    pub const DISABLE_VOLTAGE: ControlWord = ControlWord(0x0000);
    /// Transitions 7, 10, 11 (bit 2 is active low).
    pub const QUICK_STOP: ControlWord = ControlWord(0x0002);
    /// Transition 15 on the rising edge of bit 7.
    pub const FAULT_RESET: ControlWord = ControlWord(0x0080);

    pub const FAULT_RESET_BIT: u16 = 1 << 7;

    pub fn fault_reset_bit(self) -> bool {
        self.0 & Self::FAULT_RESET_BIT != 0
    }
}

/// Statusword 0x6041.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StatusWord(pub u16);

impl StatusWord {
    pub fn state(self) -> State {
        State::from_statusword(self.0)
    }
    pub fn voltage_enabled(self) -> bool {
        self.0 & (1 << 4) != 0
    }
    pub fn warning(self) -> bool {
        self.0 & (1 << 7) != 0
    }
    pub fn target_reached(self) -> bool {
        self.0 & (1 << 10) != 0
    }
    pub fn internal_limit_active(self) -> bool {
        self.0 & (1 << 11) != 0
    }
    /// CSP: drive follows the target.
    pub fn drive_follows_target(self) -> bool {
        self.0 & (1 << 12) != 0
    }
    /// CSP: following error.
    pub fn following_error(self) -> bool {
        self.0 & (1 << 13) != 0
    }
    /// MCM profile bit 14: emergency stop / safe torque off input active.
    pub fn emergency_stop(self) -> bool {
        self.0 & (1 << 14) != 0
    }
    /// MCM profile bit 15: the axis is on the positive side of its light barrier.
    pub fn light_barrier(self) -> bool {
        self.0 & (1 << 15) != 0
    }
}

/// Drive state, decoded from the statusword by the CiA 402 mask table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum State {
    /// No statusword yet, or one that matches no row of the table.
    #[default]
    Unknown,
    NotReadyToSwitchOn,
    SwitchOnDisabled,
    ReadyToSwitchOn,
    SwitchedOn,
    OperationEnabled,
    QuickStopActive,
    FaultReactionActive,
    Fault,
}

impl State {
    pub fn from_statusword(sw: u16) -> State {
        match (sw & 0x4F, sw & 0x6F) {
            (0x00, _) => State::NotReadyToSwitchOn,
            (0x40, _) => State::SwitchOnDisabled,
            (0x0F, _) => State::FaultReactionActive,
            (0x08, _) => State::Fault,
            (_, 0x21) => State::ReadyToSwitchOn,
            (_, 0x23) => State::SwitchedOn,
            (_, 0x27) => State::OperationEnabled,
            (_, 0x07) => State::QuickStopActive,
            _ => State::Unknown,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            State::Unknown => "UNKNOWN",
            State::NotReadyToSwitchOn => "NOT READY TO SWITCH ON",
            State::SwitchOnDisabled => "SWITCH ON DISABLED",
            State::ReadyToSwitchOn => "READY TO SWITCH ON",
            State::SwitchedOn => "SWITCHED ON",
            State::OperationEnabled => "OPERATION ENABLED",
            State::QuickStopActive => "QUICK STOP ACTIVE",
            State::FaultReactionActive => "FAULT REACTION ACTIVE",
            State::Fault => "FAULT",
        }
    }

    pub fn is_fault(self) -> bool {
        matches!(self, State::Fault | State::FaultReactionActive)
    }
}

impl core::fmt::Display for State {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// Where the master wants the drive to be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// Power stage off, no torque (the `Disable` request).
    SwitchOnDisabled,
    /// Power stage on, following the setpoints.
    OperationEnabled,
    /// Decelerate with the quick-stop ramp; the profile's drive then goes to SWITCH ON
    /// DISABLED by itself (0x605A = 2).
    QuickStop,
}

/// The controlword for the next hop from `state` towards `target`.
///
/// `prev` is the controlword sent in the previous cycle and `reset_fault` says whether the
/// master currently wants FAULT to be reset: in FAULT the result is then `0x0000` when `prev`
/// had bit 7 set and `0x0080` otherwise, so every two cycles produce one rising edge. Without
/// `reset_fault`, FAULT is held with `0x0000`.
///
/// Transition table (CiA 402 numbers):
///
/// | state \ target | OperationEnabled | SwitchOnDisabled | QuickStop |
/// |---|---|---|---|
/// | NOT READY / UNKNOWN / FAULT REACTION | 0x0000 (wait) | 0x0000 | 0x0000 |
/// | SWITCH ON DISABLED | 0x0006 (2) | 0x0000 | 0x0000 |
/// | READY TO SWITCH ON | 0x0007 (3) | 0x0000 (7) | 0x0002 (7) |
/// | SWITCHED ON | 0x000F (4) | 0x0000 (10) | 0x0002 (10) |
/// | OPERATION ENABLED | 0x000F (stay) | 0x0000 (9) | 0x0002 (11) |
/// | QUICK STOP ACTIVE | 0x0000 (12) | 0x0000 (12) | 0x0002 (stay) |
/// | FAULT | edge (15) or 0x0000 | edge or 0x0000 | edge or 0x0000 |
pub fn next_controlword(
    state: State,
    target: Target,
    prev: ControlWord,
    reset_fault: bool,
) -> ControlWord {
    use State as S;
    use Target as T;
    match (state, target) {
        (S::Fault, _) => {
            if reset_fault && !prev.fault_reset_bit() {
                ControlWord::FAULT_RESET
            } else {
                ControlWord::DISABLE_VOLTAGE
            }
        }
        (S::Unknown | S::NotReadyToSwitchOn | S::FaultReactionActive, _) => {
            ControlWord::DISABLE_VOLTAGE
        }
        (S::SwitchOnDisabled, T::OperationEnabled) => ControlWord::SHUTDOWN,
        (S::ReadyToSwitchOn, T::OperationEnabled) => ControlWord::SWITCH_ON,
        (S::SwitchedOn | S::OperationEnabled, T::OperationEnabled) => ControlWord::ENABLE_OPERATION,
        // Leave QUICK STOP ACTIVE through SWITCH ON DISABLED (12); re-enable from there.
        (S::QuickStopActive, T::OperationEnabled | T::SwitchOnDisabled) => {
            ControlWord::DISABLE_VOLTAGE
        }
        (S::QuickStopActive, T::QuickStop) => ControlWord::QUICK_STOP,
        (S::SwitchOnDisabled, T::SwitchOnDisabled | T::QuickStop) => ControlWord::DISABLE_VOLTAGE,
        (S::ReadyToSwitchOn | S::SwitchedOn | S::OperationEnabled, T::SwitchOnDisabled) => {
            ControlWord::DISABLE_VOLTAGE
        }
        (S::ReadyToSwitchOn | S::SwitchedOn | S::OperationEnabled, T::QuickStop) => {
            ControlWord::QUICK_STOP
        }
    }
}

/// The state a CiA 402 drive reaches when it applies `cw` in `state` (transitions 2..12 and
/// 15; automatic transitions are not modelled). Used by tests and by fakes of a drive.
pub fn apply_controlword(state: State, cw: ControlWord, prev: ControlWord) -> State {
    let c = cw.0;
    let disable_voltage = c & 0x0002 == 0;
    let quick_stop = c & 0x0006 == 0x0002;
    let shutdown = c & 0x0087 == 0x0006;
    let switch_on = c & 0x008F == 0x0007;
    let enable = c & 0x008F == 0x000F;
    use State as S;
    match state {
        S::Fault if cw.fault_reset_bit() && !prev.fault_reset_bit() => S::SwitchOnDisabled,
        S::SwitchOnDisabled if shutdown => S::ReadyToSwitchOn,
        S::ReadyToSwitchOn if switch_on => S::SwitchedOn,
        S::ReadyToSwitchOn if disable_voltage || quick_stop => S::SwitchOnDisabled,
        S::SwitchedOn if enable => S::OperationEnabled,
        S::SwitchedOn if shutdown => S::ReadyToSwitchOn,
        S::SwitchedOn if disable_voltage || quick_stop => S::SwitchOnDisabled,
        S::OperationEnabled if switch_on => S::SwitchedOn,
        S::OperationEnabled if shutdown => S::ReadyToSwitchOn,
        S::OperationEnabled if disable_voltage => S::SwitchOnDisabled,
        S::OperationEnabled if quick_stop => S::QuickStopActive,
        S::QuickStopActive if disable_voltage => S::SwitchOnDisabled,
        s => s,
    }
}

/// A representative statusword for `state` (voltage enabled where it applies, quick stop
/// bit 5 inactive-high except in QUICK STOP ACTIVE).
pub fn statusword_for(state: State) -> StatusWord {
    StatusWord(match state {
        State::Unknown => 0x0001,
        State::NotReadyToSwitchOn => 0x0000,
        State::SwitchOnDisabled => 0x0250,
        State::ReadyToSwitchOn => 0x0231,
        State::SwitchedOn => 0x0233,
        State::OperationEnabled => 0x0237,
        State::QuickStopActive => 0x0217,
        State::FaultReactionActive => 0x021F,
        State::Fault => 0x0218,
    })
}

#[cfg(test)]
mod tests;
