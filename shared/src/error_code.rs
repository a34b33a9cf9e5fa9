//! # Every error code of the MCM, defined once
//!
//! Each ERROR result of every interface carries `error_code`, the stable snake_case name of
//! why the MCM did not do what it was asked (or why it stopped on its own): clients read the
//! code, never the words. The table in `error_codes!` below is the one list: a code's name,
//! what it means and what to do about it, and, for the reasons the real-time core gives, the
//! number that carries it through shared memory ([`RejectCode`], whose numbers never change:
//! clients of other languages and the shared-memory layout depend on them).
//! [`crate::reply::Reason`] gives each of the core's reasons its figures and words; the
//! gateway's own errors (a line that is no command, an argument out of range, the access
//! rules, the connection's limits, the core unreachable) have the codes of the second part.
//!
//! `docs/protocol.md` ("Error codes") lists the table as [`markdown_table`] writes it, and a
//! test of this crate checks that it does; the clients' enums (Python's `ErrorCode`, the C
//! API's `mcm_error_code_t`, the pendant's list) are generated from it or checked against it.
//!
//! ```
//! use mcm_shared::error_code::ErrorCode;
//! use mcm_shared::mode::RejectCode;
//! assert_eq!(ErrorCode::NotOwner.as_str(), "not_owner");
//! assert_eq!(ErrorCode::from_name("wrong_mode"), Some(ErrorCode::WrongMode));
//! assert_eq!(RejectCode::NotOwner.to_wire(), 19);
//! assert_eq!(RejectCode::NotOwner.error_code(), Some(ErrorCode::NotOwner));
//! assert_eq!(ErrorCode::UnknownCommand.reject_code(), None);
//! ```
//!
//! Not used inside the real-time cycle, apart from [`RejectCode`].

use crate::mode::{UnknownValue, wire_enum};
use core::fmt;

macro_rules! error_codes {
    (
        core { $($cv:ident = $num:literal, $cname:literal, $cmeaning:literal, $cdo:literal;)* }
        gateway { $($gv:ident, $gname:literal, $gmeaning:literal, $gdo:literal;)* }
    ) => {
        wire_enum!(
            /// Why a command was refused or failed, or which safety check tripped: the code on
            /// the wire. [`crate::reply::Reason`] is the typed form with its figures;
            /// `Reason::to_wire` and `Reason::from_wire` alone define what a reply's `axis` and
            /// `values` carry. Every code but `None` is an [`ErrorCode`]
            /// ([`RejectCode::error_code`]).
            RejectCode, "reject code" {
                /// No reason (a zeroed sample).
                None = 0 => "none",
                $(#[doc = $cmeaning] $cv = $num => $cname,)*
            }
        );

        /// The stable name of every error an interface of the MCM reports (`error_code`): the
        /// real-time core's reasons (with a [`RejectCode`]) first, then the gateway's own.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum ErrorCode {
            $(#[doc = $cmeaning] $cv,)*
            $(#[doc = $gmeaning] $gv,)*
        }

        impl ErrorCode {
            /// Every code, in the order of the table (the core's first).
            pub const ALL: &'static [ErrorCode] = &[$(ErrorCode::$cv,)* $(ErrorCode::$gv,)*];

            /// The name on the wire (`error_code`, and `check` of a safety error).
            pub const fn as_str(self) -> &'static str {
                match self {
                    $(ErrorCode::$cv => $cname,)*
                    $(ErrorCode::$gv => $gname,)*
                }
            }

            /// What it means, for people (one sentence).
            pub const fn meaning(self) -> &'static str {
                match self {
                    $(ErrorCode::$cv => $cmeaning,)*
                    $(ErrorCode::$gv => $gmeaning,)*
                }
            }

            /// What a client or an operator does about it.
            pub const fn remedy(self) -> &'static str {
                match self {
                    $(ErrorCode::$cv => $cdo,)*
                    $(ErrorCode::$gv => $gdo,)*
                }
            }

            /// The shared-memory code of a reason of the real-time core; `None` for the
            /// gateway's own errors.
            pub const fn reject_code(self) -> Option<RejectCode> {
                match self {
                    $(ErrorCode::$cv => Some(RejectCode::$cv),)*
                    $(ErrorCode::$gv => None,)*
                }
            }
        }

        impl RejectCode {
            /// Its [`ErrorCode`]; `None` for [`RejectCode::None`].
            pub const fn error_code(self) -> Option<ErrorCode> {
                match self {
                    RejectCode::None => None,
                    $(RejectCode::$cv => Some(ErrorCode::$cv),)*
                }
            }
        }
    };
}

error_codes! {
    core {
        WrongMode = 1, "wrong_mode",
            "The command is not allowed in the current operating mode.",
            "Bring the arm into a mode that accepts it (`help <command>` names the modes), e.g. `hold` first.";
        NotCalibrated = 2, "not_calibrated",
            "An axis the command needs is not calibrated (the error names it).",
            "Run `calibrate` (from HOLD), then send the command again.";
        EmergencyStop = 3, "emergency_stop",
            "The emergency stop is pressed; as a safety check: it was pressed and the arm stopped.",
            "Release the emergency stop, then send `hold`.";
        DriveDisconnected = 4, "drive_disconnected",
            "A drive does not answer on the bus (the error names the axis); as a safety check: it stopped answering and the arm stopped.",
            "Check the drive's power and cabling; once it answers again, `hold` enables it.";
        DriveFault = 5, "drive_fault",
            "A drive is in fault (the error gives its error code).",
            "Look the drive's error code up in its manual and remove the cause; `hold` resets the fault.";
        OutOfRange = 6, "out_of_range",
            "A value is outside its allowed range (the error names the argument, the value and the range).",
            "Send a value within the range the error names.";
        NotAvailable = 7, "not_available",
            "The command is not implemented by this MCM version.",
            "Use another command, or an MCM version that has it.";
        NotSimulated = 8, "not_simulated",
            "The command needs the simulated robot (`sim`).",
            "Run the MCM with the simulated robot for fault injection.";
        QueueFull = 9, "queue_full",
            "The PVT queue cannot take the batch; nothing of it was queued.",
            "Wait until the queue has room (`status` detail `pvt_queue`), or send fewer points.";
        PositionLimit = 10, "position_limit",
            "Safety check: an axis went beyond its position limit; the arm stopped (mode ERROR).",
            "Find out why (the flight recorder), then `hold`; move the axis back within its limits.";
        VelocityLimit = 11, "velocity_limit",
            "Safety check: an axis moved faster than its velocity limit; the arm stopped (mode ERROR).",
            "Find out why (the flight recorder), then `hold`.";
        BrakingDistance = 12, "braking_distance",
            "Safety check: an axis could no longer stop before its limit; the arm stopped (mode ERROR).",
            "Command slower motion near the limits, then `hold`.";
        FollowingError = 13, "following_error",
            "Safety check: an axis is too far from its commanded position (blocked, overloaded or a collision); the arm stopped (mode ERROR).",
            "Remove what holds the arm, then `hold`.";
        CalibrationFailed = 14, "calibration_failed",
            "A calibration could not find or confirm its reference (the error says how).",
            "Remove what may be in the way, check the axis, and `calibrate` again.";
        Aborted = 15, "aborted",
            "The command was superseded by another command or a mode change before it finished.",
            "Nothing, if that was intended; otherwise send it again.";
        Busy = 16, "busy",
            "A motion is in progress.",
            "Wait until it ends, or send `hold` to stop it.";
        PvtPoint = 17, "pvt_point",
            "A PVT point breaks a position, velocity or acceleration limit; nothing was queued.",
            "Correct the point the error names and send the batch again.";
        Unreachable = 18, "unreachable",
            "A target position is outside the reachable range (the limits less the safety margin), or no joint position within it puts the TCP at a Cartesian pose (the error says why).",
            "Send a target within the range the error names, or a pose the arm reaches.";
        NotOwner = 19, "not_owner",
            "Another client controls the arm; only `hold` and state reads are open to others.",
            "Wait until it sends `release_control` or disconnects, then `take_control`.";
        ShuttingDown = 20, "shutting_down",
            "The MCM is shutting down: the arm is being stopped and its drives disabled.",
            "Nothing to do; connect again once the MCM runs again.";
        Overload = 21, "overload",
            "Safety check: an axis derated by i2t (its motor hot) cannot hold; the drives of the braked axes are powered off and the brakes hold the arm.",
            "Let the motor cool, then `hold` (refused with `overload` until the derating has ended).";
        NotIdentifiable = 22, "not_identifiable",
            "`identify_payload` from this pose: the poses it would measure at, within the reachable range, do not tell the load's mass and centre of mass apart (the error gives the condition number and its limit); nothing moved.",
            "Move the arm away from the limits and from the upright pose (e.g. the elbow bent, the wrist away from its limits), then send it again.";
    }
    gateway {
        InvalidJson, "invalid_json",
            "The line is not a JSON object of ASCII text (bad syntax, a key repeated, not an object).",
            "Send one JSON object per line, e.g. `{\"command\":\"status\"}`.";
        InvalidCommand, "invalid_command",
            "The JSON object is not a command: no \"command\" string, a field other than \"command\" and \"arguments\", or \"arguments\" not an object.",
            "Send `{\"command\":\"<name>\",\"arguments\":{...}}`.";
        UnknownCommand, "unknown_command",
            "No command of that name (the error suggests the nearest and lists all).",
            "Correct the command's name.";
        UnknownArgument, "unknown_argument",
            "The command has no argument of that name (the error lists its arguments).",
            "Correct the argument's name.";
        MissingArgument, "missing_argument",
            "A required argument was not given.",
            "Add the argument the error names.";
        InvalidArgument, "invalid_argument",
            "An argument's value is of the wrong type or not one of the values allowed (the error says what is expected).",
            "Send a value of the kind the error names.";
        LineTooLong, "line_too_long",
            "The command is longer than 64 KiB; the connection is closed.",
            "Send shorter commands (split a `pvt_points` batch), then connect again.";
        LineTimeout, "line_timeout",
            "Spontaneous: a command line was started but not completed within the line timeout; the connection is closed.",
            "Send each command as one complete line, then connect again.";
        IdleTimeout, "idle_timeout",
            "Spontaneous: no command within the idle timeout; the connection is closed.",
            "Send commands (e.g. `status`) more often, or connect again.";
        Evicted, "evicted",
            "Spontaneous: the connection was closed to make room for a new one (it was the longest idle).",
            "Connect again; keep connections busy or use fewer.";
        TooManyConnections, "too_many_connections",
            "The port (or ZeroMQ's peer table) is at its connection limit; this connection was refused.",
            "Close a connection you no longer need, or try again later.";
        TooManyRequests, "too_many_requests",
            "Too many requests of this ZeroMQ peer already wait for their replies; nothing was done.",
            "Send the next request after a reply.";
        NetworkRefused, "network_refused",
            "Motion commands are not accepted from this network (`[gateway.access] motion_networks`).",
            "Connect from an allowed network; `hold`, `status` and `info` stay open.";
        NotAuthenticated, "not_authenticated",
            "This MCM requires the shared secret before a client may move the arm.",
            "Send `authenticate` with the secret first.";
        WrongSecret, "wrong_secret",
            "The secret presented with `authenticate` is wrong.",
            "Ask the robot's operator for the shared secret.";
        RemoteSimRefused, "remote_sim_refused",
            "Fault injection (`sim`) is accepted only from loopback.",
            "Send `sim` from the robot's computer, or start the MCM with --allow-remote-sim.";
        CoreUnavailable, "core_unavailable",
            "The real-time core (mcm-rt) is not running or cannot be reached; the command was not executed.",
            "Start mcm-rt (the `mcm` launcher starts both processes), then send the command again.";
        OutcomeUnknown, "outcome_unknown",
            "The command was sent to the real-time core but its answer never came: it may or may not have been executed.",
            "Read the state (`status`) to learn what happened; never assume it failed.";
        VersionMismatch, "version_mismatch",
            "The real-time core and the gateway are from different MCM versions: an answer or a state could not be read.",
            "Rebuild and install mcm-rt and the gateway from the same version.";
        CoreStopping, "core_stopping",
            "Spontaneous: the real-time core was asked to stop and starts its controlled stop; every command but `status` is refused with `shutting_down` from now on.",
            "Stop sending motion; connect again once the MCM runs again.";
        CoreStopped, "core_stopped",
            "Spontaneous: the real-time core stopped after its controlled stop (arm at standstill, drives disabled); commands fail until it runs again.",
            "Start the MCM again.";
        CoreVanished, "core_vanished",
            "Spontaneous: the real-time core stopped publishing its state without shutting down (killed or crashed); the drives stop on their heartbeat timeout.",
            "Find out why (the system journal), then start the MCM again.";
        GatewayStopping, "gateway_stopping",
            "Spontaneous: the gateway was asked to stop; this is the connection's last line.",
            "Connect again once the MCM runs again.";
        EventsLost, "events_lost",
            "Spontaneous: safety errors (or states, on ZeroMQ) were not delivered: the reader fell behind.",
            "Read faster; `status` shows the last safety error and the present state.";
        InternalError, "internal_error",
            "The gateway could not handle the command (a fault of the gateway); nothing was done.",
            "Report it with the gateway's log; send the command again.";
    }
}

impl ErrorCode {
    /// Whether an ERROR of this code is spontaneous, on a connection: it answers no command
    /// (a notice about the MCM's life or about the connection; a safety error names its
    /// `check` besides). Every code is decided here: a new code does not compile until it is.
    pub const fn is_spontaneous(self) -> bool {
        use ErrorCode::*;
        match self {
            CoreStopping | CoreStopped | CoreVanished | GatewayStopping | IdleTimeout
            | LineTimeout | Evicted | TooManyConnections | EventsLost => true,
            WrongMode | NotCalibrated | EmergencyStop | DriveDisconnected | DriveFault
            | OutOfRange | NotAvailable | NotSimulated | QueueFull | PositionLimit
            | VelocityLimit | BrakingDistance | FollowingError | CalibrationFailed | Aborted
            | Busy | PvtPoint | Unreachable | NotOwner | ShuttingDown | Overload
            | NotIdentifiable | InvalidJson | InvalidCommand | UnknownCommand | UnknownArgument
            | MissingArgument | InvalidArgument | LineTooLong | TooManyRequests
            | NetworkRefused | NotAuthenticated | WrongSecret | RemoteSimRefused
            | CoreUnavailable | OutcomeUnknown | VersionMismatch | InternalError => false,
        }
    }

    /// The code called `name` (as [`ErrorCode::as_str`] writes it).
    pub fn from_name(name: &str) -> Option<ErrorCode> {
        ErrorCode::ALL.iter().copied().find(|c| c.as_str() == name)
    }
}

impl fmt::Display for ErrorCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[allow(clippy::derivable_impls)] // the wire_enum! macro derives no Default
impl Default for RejectCode {
    fn default() -> Self {
        RejectCode::None
    }
}

/// The table of `docs/protocol.md`, "Error codes": one row per code, its name, its number on
/// the wire (the core's reasons), what it means and what to do.
pub fn markdown_table() -> String {
    let mut s =
        String::from("| `error_code` | wire | meaning | what to do |\n| --- | --- | --- | --- |\n");
    for c in ErrorCode::ALL {
        let wire = c
            .reject_code()
            .map_or(String::from("-"), |r| r.to_wire().to_string());
        s.push_str(&format!(
            "| `{}` | {wire} | {} | {} |\n",
            c.as_str(),
            c.meaning(),
            c.remedy()
        ));
    }
    s
}

#[cfg(test)]
mod tests;
