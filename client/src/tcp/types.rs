//! The typed results of the JSON protocol (`docs/protocol.md`, "Results"), parsed by
//! `result_type`. Fields the manual names are required; the others are optional, so a newer
//! MCM that adds fields is still read.

use crate::NUM_AXES;
use mcm_shared::mode::{Mode, RejectCode};
use serde::Deserialize;

/// Six values, one per axis.
pub type Six = [f64; NUM_AXES];

/// `axis_states` of a `status` result.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct AxisStates {
    /// `CLOCK_MONOTONIC` of the cycle that measured the values [s], per axis.
    pub time: Six,
    /// [deg]
    pub position: Six,
    /// [deg/s]
    pub velocity: Six,
    /// [deg/s^2]
    pub acceleration: Six,
    /// Motor currents [A].
    pub current: Six,
}

/// A `status` result: the answer to `status`, `hold`, `release`, `pvt`, `torque_control`, and
/// the spontaneous status of a TORQUE_CONTROL session.
#[derive(Debug, Clone, PartialEq)]
pub struct Status {
    pub mode: Mode,
    pub axis_states: AxisStates,
    /// With `detail`: the drives, the emergency stop and the calibration in words.
    pub hardware_status: Option<String>,
    /// With `detail`: the detail object (`docs/protocol.md`, "status"), typed in parts.
    pub detail: Option<Detail>,
}

impl Status {
    /// The cycle's time [s] (`CLOCK_MONOTONIC` of the robot's computer).
    pub fn time(&self) -> f64 {
        self.axis_states.time[0]
    }
}

/// The PVT queue of a detailed status.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct PvtQueue {
    pub queued: u32,
    pub capacity: u32,
    pub starved: bool,
}

/// The `detail` object of a detailed status: the fields a program needs typed, and the whole
/// object as JSON in `raw`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct Detail {
    /// Cycle counter.
    pub cycle: u64,
    pub calibrated: [bool; NUM_AXES],
    pub all_calibrated: bool,
    pub measured_position: Six,
    pub commanded_position: Six,
    pub following_error: Six,
    pub emergency_stop: bool,
    pub pvt_queue: PvtQueue,
    #[serde(skip)]
    pub raw: serde_json::Value,
}

/// Limits of one axis, from `info`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct AxisInfo {
    pub axis: u8,
    pub name: String,
    /// [deg]
    pub min_position: f64,
    pub max_position: f64,
    /// [deg/s]
    pub max_velocity: f64,
    /// [deg/s^2]
    pub max_acceleration: f64,
    /// Peak joint torque [Nm].
    pub max_torque: f64,
    pub light_barrier: bool,
}

/// The `initialization` result of `info`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct Info {
    pub num_axes: u32,
    pub version: String,
    pub robot: String,
    /// Cycle period [s].
    pub cycle_time: f64,
    pub simulated: bool,
    pub axes: Vec<AxisInfo>,
}

/// The `move_all` result: the move the MCM planned.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct MoveAllResult {
    /// Peak velocity of each axis [deg/s].
    pub velocities: Six,
    /// The axis (1..6) that would take longest on its own.
    pub longest: u8,
    /// Time from now to the target [s].
    pub max_time_to_target: f64,
}

/// The `sim` result: the simulation's ground truth.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct SimResult {
    /// Joint angles [deg].
    pub true_position: Six,
    /// [deg/s]
    pub true_velocity: Six,
    pub emergency_stop: bool,
}

/// Options of `calibrate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CalibrateOptions {
    pub which: Option<mcm_shared::command::Which>,
    pub elbow_direction: mcm_shared::command::Direction,
    pub wrist_direction: mcm_shared::command::Direction,
    pub force_mechanical_stop: bool,
}

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
            timeout_s: Some(1.0),
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
            timeout_s: Some(1.0),
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
