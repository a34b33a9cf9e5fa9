//! Operating modes, command kinds and the typed reasons the real-time core gives when it refuses
//! or fails a command. They travel through shared memory as `u32`; each enum converts both ways,
//! and an unknown number is an error, never a silent default.

use core::fmt;

/// A `u32` on the wire that is not a known value of the named enum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("{what} {value} is not known to this MCM version")]
pub struct UnknownValue {
    pub what: &'static str,
    pub value: u32,
}

macro_rules! wire_enum {
    ($(#[$m:meta])* $name:ident, $what:literal { $($(#[$vm:meta])* $variant:ident = $num:literal => $text:literal,)* }) => {
        $(#[$m])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[repr(u32)]
        pub enum $name { $($(#[$vm])* $variant = $num,)* }

        impl $name {
            /// Every value, in wire order.
            pub const ALL: &'static [$name] = &[$($name::$variant,)*];

            /// The name used in the protocol.
            pub const fn as_str(self) -> &'static str {
                match self { $($name::$variant => $text,)* }
            }

            /// The value as sent through shared memory.
            pub const fn to_wire(self) -> u32 {
                self as u32
            }
        }

        impl TryFrom<u32> for $name {
            type Error = UnknownValue;
            fn try_from(value: u32) -> Result<Self, UnknownValue> {
                match value {
                    $($num => Ok($name::$variant),)*
                    _ => Err(UnknownValue { what: $what, value }),
                }
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.as_str())
            }
        }
    };
}
pub(crate) use wire_enum;

/// Why a command was refused or failed, or which safety check tripped: defined with every
/// other error code in [`crate::error_code`].
pub use crate::error_code::RejectCode;

wire_enum!(
    /// The operating mode, as reported in `operating_mode`.
    Mode, "operating mode" {
        /// Drives powered off, not calibrated (the mode at start-up).
        Off = 0 => "OFF",
        /// A safety check tripped; axes stopped. `hold` tries to clear it.
        Error = 1 => "ERROR",
        /// Axes kept at their current positions.
        Hold = 2 => "HOLD",
        /// Axes can be moved by hand (gravity and friction compensated).
        Release = 3 => "RELEASE",
        /// Torques given by an external controller.
        TorqueControl = 4 => "TORQUE_CONTROL",
        /// Smooth position control (move_axis, move_all, pvt_points).
        Pvt = 5 => "PVT",
        /// Calibration running.
        Calibration = 6 => "CALIBRATION",
        /// Joint velocities given by an external controller (`set_velocities`), ramped within
        /// the acceleration and jerk limits and braked before the joint limits.
        VelocityControl = 7 => "VELOCITY_CONTROL",
    }
);

#[allow(clippy::derivable_impls)] // the wire_enum! macro derives no Default
impl Default for Mode {
    fn default() -> Self {
        Mode::Off
    }
}

wire_enum!(
    /// What a command sample asks the real-time core to do.
    CommandKind, "command kind" {
        Status = 1 => "status",
        Hold = 2 => "hold",
        Info = 3 => "info",
        Calibrate = 4 => "calibrate",
        Release = 5 => "release",
        TorqueControl = 6 => "torque_control",
        Pvt = 7 => "pvt",
        MoveAxis = 8 => "move_axis",
        MoveAll = 9 => "move_all",
        PvtPoints = 10 => "pvt_points",
        SetTorques = 11 => "set_torques",
        Sim = 12 => "sim",
        /// Take control of the arm's motion (see [`CommandKind::needs_control`]).
        TakeControl = 13 => "take_control",
        /// Give up control of the arm's motion.
        ReleaseControl = 14 => "release_control",
        /// The client is gone (its connection closed): it loses control, and a motion or
        /// torque session it owned ends in a controlled stop to HOLD.
        ClientGone = 15 => "client_gone",
        /// Enter VELOCITY_CONTROL (from HOLD).
        VelocityControl = 16 => "velocity_control",
        /// The joint velocities in VELOCITY_CONTROL.
        SetVelocities = 17 => "set_velocities",
        /// The tool the arm carries (TCP and load), from the next cycle.
        SetTool = 18 => "set_tool",
        /// Estimate the load on the flange by moving the wrist through poses (from HOLD).
        IdentifyPayload = 19 => "identify_payload",
        /// The TCP's velocity (linear and angular, base or tool frame) in VELOCITY_CONTROL.
        SetCartesianVelocity = 20 => "set_cartesian_velocity",
        /// The TCP on a straight line to a target (PVT), planned beside the cycle.
        MoveLinear = 21 => "move_linear",
    }
);

wire_enum!(
    /// How the real-time core answered a command.
    ReplyStatus, "reply status" {
        /// Done (or accepted, for commands that start a motion).
        Ok = 0 => "OK",
        /// Refused; `code` says why, nothing changed.
        Rejected = 1 => "REJECTED",
        /// Accepted but failed while running (e.g. calibration could not find its stop).
        Failed = 2 => "FAILED",
    }
);

impl CommandKind {
    /// Whether the command stops the arm (`hold`, and `client_gone`, which stops what a gone
    /// owner drove): stops go out ahead of other clients' commands, in the gateway and in the
    /// real-time core alike.
    pub const fn is_stop(self) -> bool {
        matches!(self, CommandKind::Hold | CommandKind::ClientGone)
    }

    /// Whether `client` may send a command that [`CommandKind::needs_control`] while `owner`
    /// controls the arm (0: nobody, who leaves it to the first such command). Client id 0 is
    /// nobody and never controls the arm.
    pub const fn may_control(owner: u64, client: u64) -> bool {
        client != 0 && (owner == 0 || owner == client)
    }

    /// Whether the command moves the arm (or changes how it is driven), so that only the client
    /// that controls the arm may send it. `hold`, state reads, `info`, `sim` and the control
    /// commands themselves are open to every client: a stop is never refused for lack of
    /// control.
    pub const fn needs_control(self) -> bool {
        matches!(
            self,
            CommandKind::Calibrate
                | CommandKind::Release
                | CommandKind::TorqueControl
                | CommandKind::Pvt
                | CommandKind::MoveAxis
                | CommandKind::MoveAll
                | CommandKind::PvtPoints
                | CommandKind::SetTorques
                | CommandKind::VelocityControl
                | CommandKind::SetVelocities
                | CommandKind::SetTool
                | CommandKind::IdentifyPayload
                | CommandKind::SetCartesianVelocity
                | CommandKind::MoveLinear
        )
    }
}

#[cfg(test)]
mod tests;
