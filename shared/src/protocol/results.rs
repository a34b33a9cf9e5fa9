//! The results of the JSON protocol (`docs/protocol.md`, "Results"), typed: the gateway builds
//! them from the real-time core's typed answers and state and writes them with
//! [`Answer::to_value`]; the clients read them with [`Answer::from_value`]; the HMI renders the
//! same types for people. Field names follow the manual. Not used inside the real-time cycle.
//!
//! ```
//! use mcm_shared::protocol::results::{Answer, Generic};
//! let line = Answer::Generic(Generic::ok()).to_value().to_string();
//! assert_eq!(line, r#"{"error_status":"OK","result_type":"generic"}"#);
//! assert_eq!(Answer::from_value(&serde_json::from_str(&line)?)?, Answer::Generic(Generic::ok()));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::NUM_AXES;
use crate::command::DecodeError;
use crate::config::RobotConfig;
use crate::error_code::ErrorCode;
use crate::mode::{CommandKind, Mode, RejectCode};
use crate::protocol::CommandError;
use crate::reply::{InfoReply, MoveAllPlan, MoveLinearPlan, Outcome, PayloadReply, SafetyError};
use crate::sample::{
    AXIS_CALIBRATED, AXIS_ENABLED, AXIS_FAULT, AXIS_I2T_DERATED, AXIS_ONLINE, ErrorRecord,
    STATE_ALL_CALIBRATED, STATE_ESTOP, STATE_NOT_REALTIME, STATE_PVT_STARVED, STATE_SHUTTING_DOWN,
    STATE_SIM_ESTOP, StateSample, TcpState,
};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::collections::BTreeMap;

mod outcome;
pub use outcome::ErrorOutcome;

/// Six values, one per axis.
pub type Six = [f64; NUM_AXES];

/// One result line of the protocol, by its `result_type`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "result_type", rename_all = "snake_case")]
pub enum Answer {
    /// OK, or an ERROR with its words (the answer to a command, or a spontaneous error).
    Generic(Generic),
    Status(Box<Status>),
    /// The answer to `info`.
    Initialization(Info),
    MoveAll(MoveAllResult),
    MoveLinear(MoveLinearResult),
    Sim(SimResult),
    InverseKinematics(InverseKinematicsResult),
    Payload(PayloadResult),
}

impl Answer {
    /// The JSON object (keys in the order serde_json's map keeps them).
    pub fn to_value(&self) -> Value {
        // Serialising these types cannot fail: every map key is a string.
        serde_json::to_value(self).unwrap_or(Value::Null)
    }

    /// Read a result line; `Err` names what is wrong with it.
    pub fn from_value(v: &Value) -> Result<Answer, ReadError> {
        let kind = v.get("result_type").ok_or(ReadError::NoResultType)?;
        let kind = kind
            .as_str()
            .ok_or_else(|| ReadError::ResultTypeNotString {
                value: crate::protocol::json::shown(kind),
            })?;
        Answer::deserialize(v).map_err(|source| ReadError::Unreadable {
            result_type: kind.chars().take(40).collect(),
            source,
        })
    }

    /// Its `result_type`, as [`Answer::to_value`] writes it.
    pub const fn result_type(&self) -> &'static str {
        match self {
            Answer::Generic(_) => "generic",
            Answer::Status(_) => "status",
            Answer::Initialization(_) => "initialization",
            Answer::MoveAll(_) => "move_all",
            Answer::MoveLinear(_) => "move_linear",
            Answer::Sim(_) => "sim",
            Answer::InverseKinematics(_) => "inverse_kinematics",
            Answer::Payload(_) => "payload",
        }
    }

    /// An ERROR with its `code` and `message`.
    pub fn error(code: ErrorCode, message: impl Into<String>) -> Answer {
        Answer::Generic(Generic::error(code, message))
    }

    /// An ERROR answering a command that ended as `outcome` ([`Generic::answer_error`]).
    pub fn answer_error(
        outcome: ErrorOutcome,
        code: ErrorCode,
        message: impl Into<String>,
    ) -> Answer {
        Answer::Generic(Generic::answer_error(outcome, code, message))
    }

    /// This result as the answer to `command` (the name as sent): an ERROR names it in
    /// `command`; any other result is unchanged.
    pub fn answering(self, command: &str) -> Answer {
        match self {
            Answer::Generic(g) => Answer::Generic(g.answering(command)),
            other => other,
        }
    }

    /// `generic` OK.
    pub fn ok() -> Answer {
        Answer::Generic(Generic::ok())
    }
}

/// A line that does not read as a result of this version ([`Answer::from_value`]).
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("no result_type")]
    NoResultType,
    #[error("result_type is {value}, not a string")]
    ResultTypeNotString { value: String },
    /// A `result_type` this version does not know, or a result whose fields do not read.
    #[error("a `{result_type}` result that does not read: {source}")]
    Unreadable {
        result_type: String,
        #[source]
        source: serde_json::Error,
    },
}

/// A state in a mode this version does not know: the real-time core is of another MCM
/// version ([`Status::from_state`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error(
    "the real-time core reports operating mode {value}, which this MCM version does not know \
     (it knows {}); mcm-rt and the gateway are from different MCM versions: rebuild both from \
     the same version",
    known_modes()
)]
pub struct UnknownMode {
    /// The state's `mode`.
    pub value: u32,
}

/// Every mode this version knows, as its number and word, for [`UnknownMode`].
fn known_modes() -> String {
    let modes: Vec<String> = Mode::ALL
        .iter()
        .map(|m| format!("{} {m}", m.to_wire()))
        .collect();
    modes.join(", ")
}

/// `error_status` of a `generic` result.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ErrorStatus {
    #[serde(rename = "OK")]
    Ok,
    #[serde(rename = "ERROR")]
    Error,
}

/// A `generic` result: OK, or an ERROR with its code and its words. An ERROR that answers a
/// command names the command and how it ended; a spontaneous safety error adds the check, the
/// axis and the flight-recorder file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Generic {
    pub error_status: ErrorStatus,
    /// The code of an ERROR ([`ErrorCode::as_str`]): what a program reads, never the words.
    /// Kept as the text received, so that a code of a newer MCM version still reads
    /// ([`Generic::code`] is `None` for it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_code: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_message: Option<String>,
    /// The command an ERROR answers, by the name it was sent with (`set_torques`); absent for a
    /// spontaneous error and for a line that names no known command.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub command: Option<String>,
    /// How the command an ERROR answers ended; absent for a spontaneous error. An outcome of
    /// a newer MCM version reads as `None`.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "ErrorOutcome::read"
    )]
    pub outcome: Option<ErrorOutcome>,
    /// The safety check that tripped ([`RejectCode::as_str`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub check: Option<String>,
    /// The axis (1 to 6) the safety check tripped on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<u8>,
    /// The flight-recorder file written when the check tripped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flight_recorder: Option<String>,
}

impl Generic {
    /// `{"result_type":"generic","error_status":"OK"}`
    pub fn ok() -> Generic {
        Generic {
            error_status: ErrorStatus::Ok,
            error_code: None,
            error_message: None,
            command: None,
            outcome: None,
            check: None,
            axis: None,
            flight_recorder: None,
        }
    }

    /// An ERROR with its code and its words.
    pub fn error(code: ErrorCode, message: impl Into<String>) -> Generic {
        Generic {
            error_status: ErrorStatus::Error,
            error_code: Some(code.as_str().to_string()),
            error_message: Some(message.into()),
            ..Generic::ok()
        }
    }

    /// An ERROR answering a command that ended as `outcome`, with its code and its words
    /// ([`Generic::answering`] names the command).
    pub fn answer_error(
        outcome: ErrorOutcome,
        code: ErrorCode,
        message: impl Into<String>,
    ) -> Generic {
        Generic {
            outcome: Some(outcome),
            ..Generic::error(code, message)
        }
    }

    /// This result as the answer to `command` (the name as sent): an ERROR names it; OK is
    /// unchanged.
    pub fn answering(mut self, command: &str) -> Generic {
        if !self.is_ok() {
            self.command = Some(command.to_string());
        }
        self
    }

    /// The ERROR of a line refused before it became a command: outcome `invalid`, and the
    /// command it names when it names a known one.
    pub fn invalid_line(e: &CommandError) -> Generic {
        let g = Generic::answer_error(ErrorOutcome::Invalid, e.code(), e.to_string());
        match e.command() {
            Some(name) => g.answering(name),
            None => g,
        }
    }

    /// The code of an ERROR, when this version knows it (`None` for OK).
    pub fn code(&self) -> Option<ErrorCode> {
        ErrorCode::from_name(self.error_code.as_deref()?)
    }

    /// How the command an ERROR answers ended, when the result says it in a way this version
    /// knows (`None` for OK, for a spontaneous error, and for an MCM too old to send it).
    pub fn outcome(&self) -> Option<ErrorOutcome> {
        self.outcome
    }

    /// Whether it is OK.
    pub fn is_ok(&self) -> bool {
        self.error_status == ErrorStatus::Ok
    }

    /// The words of an ERROR ("" for OK).
    pub fn message(&self) -> &str {
        self.error_message.as_deref().unwrap_or_default()
    }

    /// The check of a safety error, when this version knows it.
    pub fn check_code(&self) -> Option<RejectCode> {
        let check = self.check.as_deref()?;
        RejectCode::ALL
            .iter()
            .copied()
            .find(|c| c.as_str() == check)
    }

    /// The words for a refused or failed command of `kind`, prefixed with the command name,
    /// and its `outcome` (a command that was done is [`Generic::ok`]). A value of an argument
    /// outside its range reads exactly as the gateway's own refusal of it (`move_axis:
    /// argument "target_position" = 175 is not allowed; expected ...`), whichever side
    /// refused; `outcome` tells which.
    pub fn reply_error(kind: CommandKind, outcome: &Outcome) -> Generic {
        let (ended, reason) = match outcome {
            Outcome::Done(_) => return Generic::ok(),
            Outcome::Refused(reason) => (ErrorOutcome::Refused, reason),
            Outcome::Failed(reason) => (ErrorOutcome::Failed, reason),
        };
        Generic::answer_error(ended, reason.error_code(), outcome.words(kind).to_string())
    }

    /// A safety error in words (without the mode and the flight-recorder file); its
    /// `error_code` is its `check`.
    pub fn safety_error(e: &SafetyError) -> Generic {
        let code = e.reason.error_code();
        Generic {
            check: Some(code.as_str().to_string()),
            axis: e.reason.axis().map(|a| a.number()),
            ..Generic::error(code, e.to_string())
        }
    }

    /// A safety error whose record this version cannot read (a core of another MCM version).
    pub fn unreadable_safety_error(e: &DecodeError) -> Generic {
        Generic::error(
            ErrorCode::VersionMismatch,
            format!(
                "safety check tripped, but its record cannot be read ({e}); mcm-rt and the gateway \
             are from different MCM versions: rebuild both from the same version"
            ),
        )
    }

    /// The safety error a state reports in words; `None` when there was none since start.
    pub fn last_error(record: &ErrorRecord) -> Option<Generic> {
        match SafetyError::decode(record) {
            Ok(e) => e.as_ref().map(Generic::safety_error),
            Err(e) => Some(Generic::unreadable_safety_error(&e)),
        }
    }

    /// A spontaneous safety error: `error` (or the decode error of its record), the mode it
    /// left the robot in and the flight-recorder file it wrote.
    pub fn safety_event(
        error: &Result<SafetyError, DecodeError>,
        mode: u32,
        file: &std::path::Path,
    ) -> Generic {
        let mut g = match error {
            Ok(e) => Generic::safety_error(e),
            Err(e) => Generic::unreadable_safety_error(e),
        };
        let mode = Mode::try_from(mode).map(Mode::as_str).unwrap_or("UNKNOWN");
        let file = file.display().to_string();
        g.error_message = Some(format!(
            "{}; mode is now {mode}; flight recorder: {file}",
            g.message()
        ));
        g.flight_recorder = Some(file);
        g
    }
}

/// A figure rounded to 6 decimals for the results.
pub fn round(x: f64) -> f64 {
    (x * 1e6).round() / 1e6
}

/// Six figures, rounded.
pub fn six(v: &Six) -> Six {
    v.map(round)
}

/// `axis_states` of a `status` result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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

/// `cartesian_state` of a `status` result: the TCP in the base frame, from the same axis values
/// as its `axis_states` (`docs/cartesian.md`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CartesianState {
    /// The TCP's origin [m].
    pub position: [f64; 3],
    /// The TCP frame's orientation, a unit quaternion `[x, y, z, w]` (`w >= 0`).
    pub orientation: [f64; 4],
    /// [m/s]
    pub linear_velocity: [f64; 3],
    /// [deg/s]
    pub angular_velocity: [f64; 3],
}

impl From<&TcpState> for CartesianState {
    /// The sample's TCP state, rounded like every figure of the results.
    fn from(t: &TcpState) -> CartesianState {
        CartesianState {
            position: t.position.map(round),
            orientation: t.orientation.map(round),
            linear_velocity: t.linear_velocity.map(round),
            angular_velocity: t.angular_velocity.map(round),
        }
    }
}

/// A `status` result: the answer to `status`, `hold`, `release`, `pvt`, `torque_control`,
/// `velocity_control`, and the spontaneous status of a TORQUE_CONTROL or VELOCITY_CONTROL
/// session.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Status {
    #[serde(rename = "operating_mode", with = "mode_word")]
    pub mode: Mode,
    pub axis_states: AxisStates,
    /// The TCP's state, once every axis is calibrated (absent before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cartesian_state: Option<CartesianState>,
    /// With `detail`: the drives, the emergency stop and the calibration in words.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hardware_status: Option<String>,
    /// With `detail`: the detail object.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub detail: Option<Detail>,
}

impl Status {
    /// The cycle's time [s] (`CLOCK_MONOTONIC` of the robot's computer).
    pub fn time(&self) -> f64 {
        self.axis_states.time[0]
    }

    /// The status of `state`, with the detail when `detail` (without `control` and `access`,
    /// which the gateway adds for the connection). `Err` when the state's mode is unknown to
    /// this version (a core of another MCM version).
    pub fn from_state(state: &StateSample, detail: bool) -> Result<Status, UnknownMode> {
        let mode = Mode::try_from(state.mode).map_err(|e| UnknownMode { value: e.value })?;
        let t = round(state.t_ns as f64 / 1e9);
        Ok(Status {
            mode,
            axis_states: AxisStates {
                time: [t; NUM_AXES],
                position: six(&state.position),
                velocity: six(&state.velocity),
                acceleration: six(&state.acceleration),
                current: six(&state.current),
            },
            cartesian_state: state.tcp_state().map(CartesianState::from),
            hardware_status: detail.then(|| hardware_status(state)),
            detail: detail.then(|| Detail::from_state(state)),
        })
    }
}

mod mode_word {
    use crate::mode::Mode;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(m: &Mode, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(m.as_str())
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Mode, D::Error> {
        let word = String::deserialize(d)?;
        Mode::ALL
            .iter()
            .copied()
            .find(|m| m.as_str() == word)
            .ok_or_else(|| serde::de::Error::custom(format!("{word} is not a known mode")))
    }
}

/// A human summary of the hardware for `hardware_status`.
pub fn hardware_status(state: &StateSample) -> String {
    let count = |bit: u32| state.axis_flags.iter().filter(|f| *f & bit != 0).count();
    let mut parts = vec![
        format!("drives online {}/6", count(AXIS_ONLINE)),
        format!("enabled {}/6", count(AXIS_ENABLED)),
    ];
    let faults = count(AXIS_FAULT);
    if faults > 0 {
        parts.push(format!("in fault {faults}"));
    }
    parts.push(format!(
        "emergency stop {}",
        if state.flags & STATE_ESTOP != 0 {
            "PRESSED"
        } else {
            "released"
        }
    ));
    parts.push(format!("calibrated {}/6", count(AXIS_CALIBRATED)));
    let derated = count(AXIS_I2T_DERATED);
    if derated > 0 {
        parts.push(format!("i2t derated {derated}"));
    }
    if state.flags & STATE_NOT_REALTIME != 0 {
        parts.push("cycle NOT real-time".into());
    }
    parts.join(", ")
}

/// The PVT queue of a detailed status.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PvtQueue {
    pub queued: u32,
    pub capacity: u32,
    pub starved: bool,
}

/// Latency figures over a window of the cycle's timing [µs].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RecentTiming {
    pub window_s: f64,
    pub cycles: u64,
    pub latency_p50_us: f64,
    pub latency_p99_us: f64,
    pub latency_p99_9_us: f64,
    pub latency_p99_99_us: f64,
    pub latency_max_us: f64,
}

/// The cycle's timing in a detailed status.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    pub period_s: f64,
    pub overruns: u64,
    pub latency_p50_us: f64,
    pub latency_p99_us: f64,
    pub latency_max_us: f64,
    pub latency_p99_9_us: f64,
    pub latency_p99_99_us: f64,
    pub cycles: u64,
    pub recent: RecentTiming,
    pub work_max_us: f64,
    pub work_budget_us: f64,
    pub over_budget: u64,
    pub realtime: bool,
}

/// The shared-memory link in a detailed status.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Ipc {
    pub command_receive_errors: u64,
}

/// `detail.bus`: the CAN bus's and the CANopen master's error counters since the core
/// started ([`crate::sample::BusCounters`]); each counts something that should not happen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct BusDetail {
    /// Frames from configured drives the master could not decode.
    pub bad_frames: u64,
    /// Frames that did not fit the cycle's frame buffer (not sent).
    pub frames_dropped: u64,
    /// Master events lost because its event ring was full.
    pub events_dropped: u64,
    /// Frames the bus refused to send or failed to receive.
    pub bus_errors: u64,
}

/// `detail.control`: who controls the arm, and whether it is this connection.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ControlDetail {
    /// The owner in words (peer address or client name); `None` when nobody controls the arm.
    pub owner: Option<String>,
    pub owner_client_id: u64,
    pub this_connection: bool,
}

/// `detail.access`: the access rules as they apply to this connection.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AccessDetail {
    pub peer: String,
    pub motion_networks: String,
    pub motion_allowed_here: bool,
    pub secret_required: bool,
    pub authenticated: bool,
    pub remote_sim: bool,
    /// Refusals since the gateway started, by kind.
    pub refused: BTreeMap<String, u64>,
}

/// The `detail` object of a detailed status.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Detail {
    /// Cycle counter.
    pub cycle: u64,
    pub calibrated: [bool; NUM_AXES],
    pub all_calibrated: bool,
    pub measured_position: Six,
    pub commanded_position: Six,
    pub following_error: Six,
    pub i2t: Six,
    pub i2t_derated: [bool; NUM_AXES],
    pub drive_online: [bool; NUM_AXES],
    pub drive_enabled: [bool; NUM_AXES],
    pub drive_fault: [bool; NUM_AXES],
    pub emergency_stop: bool,
    pub shutting_down: bool,
    pub pvt_queue: PvtQueue,
    pub timing: Timing,
    pub ipc: Ipc,
    pub bus: BusDetail,
    /// The active tool, as `set_tool` takes it.
    pub tool: crate::tool::Tool,
    /// Added by the gateway for the connection that asked.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control: Option<ControlDetail>,
    /// Added by the gateway for the connection that asked.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub access: Option<AccessDetail>,
}

impl Detail {
    /// The detail of `state` (without `control` and `access`).
    pub fn from_state(state: &StateSample) -> Detail {
        let bits = |bit: u32| state.axis_flags.map(|f| f & bit != 0);
        let us = |ns: u64| ns as f64 / 1e3;
        let tm = &state.timing;
        Detail {
            cycle: state.seq,
            calibrated: bits(AXIS_CALIBRATED),
            all_calibrated: state.flags & STATE_ALL_CALIBRATED != 0,
            measured_position: six(&state.measured_position),
            commanded_position: six(&state.commanded_position),
            following_error: six(&state.following_error),
            i2t: six(&state.i2t),
            i2t_derated: bits(AXIS_I2T_DERATED),
            drive_online: bits(AXIS_ONLINE),
            drive_enabled: bits(AXIS_ENABLED),
            drive_fault: bits(AXIS_FAULT),
            emergency_stop: state.flags & STATE_ESTOP != 0,
            shutting_down: state.flags & STATE_SHUTTING_DOWN != 0,
            pvt_queue: PvtQueue {
                queued: state.pvt_queued,
                capacity: state.pvt_capacity,
                starved: state.flags & STATE_PVT_STARVED != 0,
            },
            timing: Timing {
                period_s: tm.period_ns as f64 / 1e9,
                overruns: tm.overruns,
                latency_p50_us: us(tm.since_start.p50_ns),
                latency_p99_us: us(tm.since_start.p99_ns),
                latency_max_us: us(tm.since_start.max_ns),
                latency_p99_9_us: us(tm.since_start.p99_9_ns),
                latency_p99_99_us: us(tm.since_start.p99_99_ns),
                cycles: tm.since_start.cycles,
                recent: RecentTiming {
                    window_s: tm.recent_window_ns as f64 / 1e9,
                    cycles: tm.recent.cycles,
                    latency_p50_us: us(tm.recent.p50_ns),
                    latency_p99_us: us(tm.recent.p99_ns),
                    latency_p99_9_us: us(tm.recent.p99_9_ns),
                    latency_p99_99_us: us(tm.recent.p99_99_ns),
                    latency_max_us: us(tm.recent.max_ns),
                },
                work_max_us: us(tm.work_max_ns),
                work_budget_us: us(tm.work_budget_ns),
                over_budget: tm.over_budget,
                realtime: state.flags & STATE_NOT_REALTIME == 0,
            },
            ipc: Ipc {
                command_receive_errors: state.command_receive_errors,
            },
            bus: BusDetail {
                bad_frames: state.bus.bad_frames,
                frames_dropped: state.bus.frames_dropped,
                events_dropped: state.bus.events_dropped,
                bus_errors: state.bus.bus_errors,
            },
            tool: crate::tool::Tool::from(&state.tool),
            control: None,
            access: None,
        }
    }
}

/// Limits of one axis, in the `initialization` result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AxisInfo {
    /// 1 to 6.
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Info {
    pub num_axes: u32,
    pub version: String,
    pub robot: String,
    /// Cycle period [s].
    pub cycle_time: f64,
    pub simulated: bool,
    pub axes: Vec<AxisInfo>,
}

impl Info {
    /// The result of `info` from the configuration and the core's answer; `simulated`: the core
    /// runs the simulated robot (its state's `STATE_SIMULATED` flag).
    pub fn new(cfg: &RobotConfig, info: &InfoReply, simulated: bool) -> Info {
        let axes = cfg
            .axes
            .iter()
            .zip(1u8..)
            .map(|(a, axis)| AxisInfo {
                axis,
                name: a.name.clone(),
                min_position: a.min_deg,
                max_position: a.max_deg,
                max_velocity: a.max_velocity_deg_s,
                max_acceleration: a.max_acceleration_deg_s2,
                max_torque: round(a.max_current_a * a.torque_per_amp()),
                light_barrier: a.calibration.light_barrier_deg.is_some(),
            })
            .collect();
        Info {
            num_axes: info.num_axes,
            version: crate::VERSION.to_string(),
            robot: cfg.robot.name.clone(),
            cycle_time: info.period_s,
            simulated,
            axes,
        }
    }
}

/// The `move_all` result: the move the MCM planned.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MoveAllResult {
    /// Peak velocity of each axis [deg/s].
    pub velocities: Six,
    /// The axis (1 to 6) that would take longest on its own.
    pub longest: u8,
    /// Time from now to the target [s].
    pub max_time_to_target: f64,
}

impl From<&MoveAllPlan> for MoveAllResult {
    fn from(plan: &MoveAllPlan) -> MoveAllResult {
        MoveAllResult {
            velocities: six(&plan.velocities_deg_s),
            longest: plan.longest.number(),
            max_time_to_target: round(plan.duration_s),
        }
    }
}

/// The `move_linear` result: the line the MCM planned.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MoveLinearResult {
    /// Time from now to the target [s].
    pub duration: f64,
    /// Each axis's position at the target [deg].
    pub joint_target: Six,
}

impl From<&MoveLinearPlan> for MoveLinearResult {
    fn from(plan: &MoveLinearPlan) -> MoveLinearResult {
        MoveLinearResult {
            duration: round(plan.duration_s),
            joint_target: six(&plan.joint_target_deg),
        }
    }
}

/// The `inverse_kinematics` result: every joint configuration that puts the TCP at the pose,
/// each within the axes' reachable ranges, the nearest to the seed first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InverseKinematicsResult {
    /// Joint angles [deg], six per solution.
    pub solutions: Vec<Six>,
}

impl InverseKinematicsResult {
    /// The result of `solutions` [deg], in their order, rounded as every figure is.
    pub fn new(solutions: impl IntoIterator<Item = Six>) -> InverseKinematicsResult {
        InverseKinematicsResult {
            solutions: solutions.into_iter().map(|q| six(&q)).collect(),
        }
    }
}

/// The `payload` result (`identify_payload`): the load the real-time core estimated.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PayloadResult {
    /// [kg]
    pub mass: f64,
    /// [m], flange frame; zeros for a load too light to place (below 0.05 kg).
    pub center_of_mass: [f64; 3],
    /// RMS over every axis and pose of the holding torque the estimate does not explain [N m].
    pub residual: f64,
}

impl From<&PayloadReply> for PayloadResult {
    fn from(p: &PayloadReply) -> PayloadResult {
        PayloadResult {
            mass: round(p.mass_kg),
            center_of_mass: p.center_of_mass_m.map(round),
            residual: round(p.residual_nm),
        }
    }
}

/// The `sim` result: the simulation's ground truth.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SimResult {
    /// Joint angles [deg].
    pub true_position: Six,
    /// [deg/s]
    pub true_velocity: Six,
    pub emergency_stop: bool,
}

impl SimResult {
    /// The ground truth a state carries.
    pub fn from_state(state: &StateSample) -> SimResult {
        SimResult {
            true_position: six(&state.sim_true_position),
            true_velocity: six(&state.sim_true_velocity),
            emergency_stop: state.flags & STATE_SIM_ESTOP != 0,
        }
    }
}

#[cfg(test)]
mod tests;
