//! The typed results of the JSON protocol (`docs/protocol.md`, "Results"): those of the
//! contract ([`mcm_shared::protocol::results`]), the options of the calls, and the events.
//! `calibrate` takes the contract's [`Calibrate`] itself (as the shared-memory client does).

use mcm_shared::mode::RejectCode;

pub use mcm_shared::command::{Calibrate, MoveLinear};
pub use mcm_shared::protocol::Pose;
pub use mcm_shared::protocol::results::{
    AxisInfo, AxisStates, CartesianState, Detail, Info, InverseKinematicsResult, MoveAllResult,
    MoveLinearResult, PayloadResult, PvtQueue, SimResult, Six, Status,
};

/// Options of `torque_control`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorqueOptions {
    /// Fall back to HOLD when no `set_torques` came for this long [s]; `None`: never.
    pub timeout_s: Option<f64>,
    /// Interval of spontaneous status results [s] (read them with `next_event`); `None`: none.
    pub dt_status_s: Option<f64>,
    /// Add the model's gravity (and 70 % of its friction) compensation to the torques.
    pub gravity_compensation: bool,
}

impl Default for TorqueOptions {
    /// The protocol's defaults: 1 s timeout, no status ticks, gravity compensated.
    fn default() -> Self {
        TorqueOptions {
            timeout_s: Some(mcm_shared::protocol::DEFAULT_MODE_TIMEOUT),
            dt_status_s: None,
            gravity_compensation: true,
        }
    }
}

/// Options of `velocity_control`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityOptions {
    /// Stop (controlled, to HOLD) when no `set_velocities` came for this long [s]; `None`:
    /// never.
    pub timeout_s: Option<f64>,
    /// Interval of spontaneous status results [s] (read them with `next_event`); `None`: none.
    pub dt_status_s: Option<f64>,
}

impl Default for VelocityOptions {
    /// The protocol's defaults: 1 s timeout, no status ticks.
    fn default() -> Self {
        VelocityOptions {
            timeout_s: Some(mcm_shared::protocol::DEFAULT_MODE_TIMEOUT),
            dt_status_s: None,
        }
    }
}

/// Something the MCM sent that answers no command of this client.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// A status of this connection's TORQUE_CONTROL or VELOCITY_CONTROL session: one every
    /// `dt_status`, and one when the mode is left (timeout, `hold`, safety stop).
    Status(Box<Status>),
    /// A safety check tripped (sent to every client): the check, the axis, the words.
    SafetyError {
        check: Option<RejectCode>,
        axis: Option<u8>,
        message: String,
        flight_recorder: Option<String>,
    },
    /// A refusal of a command that has no result on success (`set_torques`,
    /// `set_velocities`).
    CommandError(crate::tcp::McmError),
    /// A notice about the MCM's own life (shutting down, the core stopped) or about this
    /// connection (closed for idleness, to make room): its words.
    Notice(String),
}

impl From<TorqueOptions> for mcm_shared::protocol::TorqueControl {
    fn from(o: TorqueOptions) -> Self {
        mcm_shared::protocol::TorqueControl {
            request: mcm_shared::command::TorqueControl {
                timeout_s: o.timeout_s,
                gravity_compensation: o.gravity_compensation,
            },
            dt_status: o.dt_status_s.unwrap_or(0.0),
        }
    }
}

impl From<VelocityOptions> for mcm_shared::protocol::VelocityControl {
    fn from(o: VelocityOptions) -> Self {
        mcm_shared::protocol::VelocityControl {
            request: mcm_shared::command::VelocityControl {
                timeout_s: o.timeout_s,
            },
            dt_status: o.dt_status_s.unwrap_or(0.0),
        }
    }
}
