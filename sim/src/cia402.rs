//! The CiA 402 power state machine of the simulated drive (`docs/drive-profile.md`, "Drive state
//! machine"): controlword decoding, transitions 1-15, the statusword encoding, and the drive
//! profile's additions (quick stop option 2: ramp down, then SWITCH ON DISABLED; fault reset on the
//! rising edge of controlword bit 7; transition 2 refused while the safe-torque-off input is
//! active).
//!
//! Runs inside the cycle: plain data, no allocation. The fault reaction (current 0) is
//! instantaneous in the simulation, so FAULT REACTION ACTIVE is never observed: transitions
//! 13 + 14 are taken at once. Transition 16 (QUICK STOP ACTIVE -> OPERATION ENABLED) does not
//! exist with quick stop option 2.
//!
//! ```
//! use mcm_sim::cia402::{State, StateMachine, StatusInputs};
//! let mut sm = StateMachine::new();
//! sm.boot_complete();
//! for cw in [0x06, 0x07, 0x0F] {
//!     sm.write_controlword(cw, true);
//! }
//! assert_eq!(sm.state(), State::OperationEnabled);
//! assert_eq!(sm.statusword(StatusInputs::default()) & 0x6F, 0x27);
//! ```

/// A CiA 402 power state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum State {
    NotReadyToSwitchOn,
    SwitchOnDisabled,
    ReadyToSwitchOn,
    SwitchedOn,
    OperationEnabled,
    QuickStopActive,
    Fault,
}

impl State {
    /// The drive controls the motor current in this state.
    pub const fn is_enabled(self) -> bool {
        matches!(self, State::OperationEnabled | State::QuickStopActive)
    }
}

/// A state change: (from, to).
pub type Transition = Option<(State, State)>;

/// Inputs shown in the statusword besides the state.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StatusInputs {
    /// Safe torque off / emergency stop input active (bit 14; clears bit 4).
    pub safe_torque_off: bool,
    /// Axis on the positive side of its light barrier (bit 15).
    pub light_barrier: bool,
    /// The drive follows the cyclic command (bit 12 in CSP/CST; only shown when enabled).
    pub following: bool,
}

/// The state machine plus the last controlword (for the fault-reset edge).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StateMachine {
    state: State,
    last_controlword: u16,
}

impl Default for StateMachine {
    fn default() -> Self {
        Self::new()
    }
}

fn is_disable_voltage(cw: u16) -> bool {
    cw & 0x82 == 0x00
}
fn is_quick_stop(cw: u16) -> bool {
    cw & 0x86 == 0x02
}
fn is_shutdown(cw: u16) -> bool {
    cw & 0x87 == 0x06
}
fn is_switch_on(cw: u16) -> bool {
    cw & 0x8F == 0x07
}
fn is_enable_operation(cw: u16) -> bool {
    cw & 0x8F == 0x0F
}

impl StateMachine {
    /// At power-up: NOT READY TO SWITCH ON (transition 0).
    pub const fn new() -> StateMachine {
        StateMachine {
            state: State::NotReadyToSwitchOn,
            last_controlword: 0,
        }
    }

    pub const fn state(&self) -> State {
        self.state
    }

    fn go(&mut self, to: State) -> Transition {
        let from = self.state;
        self.state = to;
        (from != to).then_some((from, to))
    }

    /// Transition 1: the drive's initialisation is complete.
    pub fn boot_complete(&mut self) -> Transition {
        match self.state {
            State::NotReadyToSwitchOn => self.go(State::SwitchOnDisabled),
            _ => None,
        }
    }

    /// A new controlword was written (by SDO or PDO). `power_ok` is false while the safe
    /// torque off input is active (then transition 2 and enabling are refused).
    pub fn write_controlword(&mut self, cw: u16, power_ok: bool) -> Transition {
        let rising_reset = cw & 0x80 != 0 && self.last_controlword & 0x80 == 0;
        self.last_controlword = cw;
        if self.state == State::Fault {
            return if rising_reset {
                self.go(State::SwitchOnDisabled)
            } else {
                None
            };
        }
        self.evaluate(cw, power_ok)
    }

    /// Re-apply the last controlword (level commands only, no edge), e.g. at every SYNC, so
    /// that a command refused earlier (STO active) takes effect once allowed.
    pub fn reevaluate(&mut self, power_ok: bool) -> Transition {
        self.evaluate(self.last_controlword, power_ok)
    }

    fn evaluate(&mut self, cw: u16, power_ok: bool) -> Transition {
        use State::*;
        match self.state {
            NotReadyToSwitchOn | Fault => None,
            SwitchOnDisabled if is_shutdown(cw) && power_ok => self.go(ReadyToSwitchOn), // 2
            SwitchOnDisabled => None,
            ReadyToSwitchOn if is_disable_voltage(cw) || is_quick_stop(cw) => {
                self.go(SwitchOnDisabled)
            } // 7
            ReadyToSwitchOn if is_switch_on(cw) && power_ok => self.go(SwitchedOn), // 3
            ReadyToSwitchOn if is_enable_operation(cw) && power_ok => self.go(OperationEnabled), // 3 + 4
            SwitchedOn if is_disable_voltage(cw) || is_quick_stop(cw) => self.go(SwitchOnDisabled), // 10
            SwitchedOn if is_shutdown(cw) => self.go(ReadyToSwitchOn), // 6
            SwitchedOn if is_enable_operation(cw) && power_ok => self.go(OperationEnabled), // 4
            OperationEnabled if is_disable_voltage(cw) => self.go(SwitchOnDisabled), // 9
            OperationEnabled if is_quick_stop(cw) => self.go(QuickStopActive), // 11
            OperationEnabled if is_shutdown(cw) => self.go(ReadyToSwitchOn), // 8
            OperationEnabled if is_switch_on(cw) => self.go(SwitchedOn), // 5
            QuickStopActive if is_disable_voltage(cw) => self.go(SwitchOnDisabled), // 12
            ReadyToSwitchOn | SwitchedOn | OperationEnabled | QuickStopActive => None,
        }
    }

    /// Transition 12 (automatic with quick stop option 2): the quick-stop ramp has ended.
    pub fn quick_stop_finished(&mut self) -> Transition {
        match self.state {
            State::QuickStopActive => self.go(State::SwitchOnDisabled),
            _ => None,
        }
    }

    /// Transitions 13 + 14: a fault. `None` if already in FAULT.
    pub fn fault(&mut self) -> Transition {
        self.go(State::Fault)
    }

    /// The power stage was switched off (safe torque off): a drive that was enabled faults;
    /// READY TO SWITCH ON / SWITCHED ON fall back to SWITCH ON DISABLED.
    pub fn power_stage_off(&mut self) -> Transition {
        match self.state {
            State::OperationEnabled | State::QuickStopActive => self.fault(),
            State::ReadyToSwitchOn | State::SwitchedOn => self.go(State::SwitchOnDisabled),
            _ => None,
        }
    }

    /// The statusword 0x6041 (bit 9 remote always set).
    pub fn statusword(&self, inputs: StatusInputs) -> u16 {
        let mut sw: u16 = match self.state {
            State::NotReadyToSwitchOn => 0x0000,
            State::SwitchOnDisabled => 0x0040,
            State::ReadyToSwitchOn => 0x0021,
            State::SwitchedOn => 0x0023,
            State::OperationEnabled => 0x0027,
            State::QuickStopActive => 0x0007,
            State::Fault => 0x0008,
        };
        sw |= 1 << 9;
        if !inputs.safe_torque_off {
            sw |= 1 << 4;
        } else {
            sw |= 1 << 14;
        }
        if inputs.light_barrier {
            sw |= 1 << 15;
        }
        if inputs.following && self.state == State::OperationEnabled {
            sw |= 1 << 12;
        }
        sw
    }
}

#[cfg(test)]
mod tests;
