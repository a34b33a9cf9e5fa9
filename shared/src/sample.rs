//! The IPC samples: fixed-size `#[repr(C)]` types shared through iceoryx2.
//!
//! iceoryx2 only compares a type's name, size and alignment when a peer opens a service; it
//! does not see field layouts. So every type name carries a version (`.v1`), every struct has
//! explicit padding, and the tests at the bottom pin size, alignment and every field offset.
//! **Any layout change must bump the version in the type name.**
//!
//! Values are in the user's units: degrees, degrees/s, degrees/s^2, amperes, newton-metres,
//! seconds. Times are `CLOCK_MONOTONIC` nanoseconds (Python: `time.monotonic_ns()`).
//!
//! ## Command arguments
//! What `CommandSample::args` and `flags` hold for each kind is defined in one place, by
//! [`crate::command::Request::encode`] and [`crate::command::Request::decode`]; replies and
//! error records likewise by [`crate::reply`]. Build samples through those types, never by
//! position.

use crate::NUM_AXES;
use crate::tool::{Tcp, Tool};
use iceoryx2::port::reader::{EntryHandle, EntryHandleError, Reader};
use iceoryx2::prelude::{ZeroCopySend, ipc};

/// Arguments in one command sample.
pub const COMMAND_ARGS: usize = 64;
/// PVT points carried by one `PvtPoints` command sample.
pub const PVT_POINTS_PER_COMMAND: usize = 4;
/// Replies in one [`ReplyBlock`].
pub const REPLY_BLOCK: usize = 16;
/// Reply blocks the state blackboard keeps (keys 1 to `REPLY_BLOCKS`): the newest
/// `REPLY_BLOCKS * REPLY_BLOCK` replies stay readable, so a reader may fall that far behind
/// (a stalled gateway) without losing one.
pub const REPLY_BLOCKS: usize = 512;
/// Replies the real-time core gives in one cycle at most (two per command served; a command
/// may also end an earlier one, e.g. `hold` answers an aborted calibration too).
pub const REPLIES_PER_CYCLE: usize = 2 * crate::service::COMMANDS_PER_CYCLE;
/// Values carried by one reply or error record.
pub const REPLY_VALUES: usize = 8;

/// `CommandSample::flags` for `PvtPoints`: this sample closes its batch.
pub const PVT_FLAG_LAST: u32 = 1 << 8;
/// `CommandSample::flags` for `TorqueControl`: torques are not added to the gravity compensation.
pub const TORQUE_FLAG_NO_GRAVITY: u32 = 1;
/// `CommandSample::flags` for `Calibrate`: use mechanical stops even where light barriers exist.
pub const CALIBRATE_FLAG_FORCE_STOP: u32 = 1;
/// `CommandSample::flags` for `IdentifyPayload`: the estimate becomes the tool's load.
pub const IDENTIFY_FLAG_APPLY: u32 = 1;
/// `CommandSample::flags` for `Sim`: power cycle the drives.
pub const SIM_FLAG_POWER_CYCLE: u32 = 1 << 11;

/// `StateSample::flags`: the emergency stop is pressed.
pub const STATE_ESTOP: u32 = 1;
/// `StateSample::flags`: the robot is the simulation (`sim_*` fields are valid).
pub const STATE_SIMULATED: u32 = 1 << 1;
/// `StateSample::flags`: every axis is calibrated.
pub const STATE_ALL_CALIBRATED: u32 = 1 << 2;
/// `StateSample::flags`: the PVT queue ran dry and the axes were stopped.
pub const STATE_PVT_STARVED: u32 = 1 << 3;
/// `StateSample::flags`: the cycle runs without real-time scheduling (see the log of mcm-rt).
pub const STATE_NOT_REALTIME: u32 = 1 << 4;
/// `StateSample::flags`: the simulated emergency switch is pressed (ground truth).
pub const STATE_SIM_ESTOP: u32 = 1 << 5;
/// `StateSample::flags`: the MCM is shutting down (stopping the arm, then disabling the drives);
/// every command but `status` is refused with `shutting_down`.
pub const STATE_SHUTTING_DOWN: u32 = 1 << 6;
/// `StateSample::flags`: `cartesian` holds the TCP's state (every axis is calibrated); when
/// clear, `cartesian` is all zeros and means nothing.
pub const STATE_CARTESIAN: u32 = 1 << 7;

/// `StateSample::axis_flags`: the axis is calibrated.
pub const AXIS_CALIBRATED: u32 = 1;
/// `StateSample::axis_flags`: the drive answers on the bus.
pub const AXIS_ONLINE: u32 = 1 << 1;
/// `StateSample::axis_flags`: the drive is in Operation Enabled.
pub const AXIS_ENABLED: u32 = 1 << 2;
/// `StateSample::axis_flags`: the drive reports a fault.
pub const AXIS_FAULT: u32 = 1 << 3;
/// `StateSample::axis_flags`: i2t protection has reduced the motor's maximum current.
pub const AXIS_I2T_DERATED: u32 = 1 << 4;

/// A command to the real-time core. See the module docs for the meaning of `args` per kind.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("mcm.CommandSample.v1")]
pub struct CommandSample {
    /// Who sent it: unique per gateway connection or controller (never 0).
    pub client_id: u64,
    /// Increasing per client; echoed in the reply.
    pub request_id: u64,
    /// [`crate::mode::CommandKind`] as `u32`.
    pub kind: u32,
    /// Kind-specific flags.
    pub flags: u32,
    pub args: [f64; COMMAND_ARGS],
}

impl Default for CommandSample {
    fn default() -> Self {
        Self {
            client_id: 0,
            request_id: 0,
            kind: 0,
            flags: 0,
            args: [0.0; COMMAND_ARGS],
        }
    }
}

/// The answer to one command, kept in a [`ReplyBlock`] of the state blackboard.
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
pub struct Reply {
    /// Position of this reply in the stream of all replies (1, 2, 3, ...; 0 = empty slot).
    pub seq: u64,
    pub client_id: u64,
    pub request_id: u64,
    /// `StateSample::seq` of the cycle that gave the reply.
    pub cycle: u64,
    /// [`crate::mode::CommandKind`] of the command answered.
    pub kind: u32,
    /// [`crate::mode::ReplyStatus`].
    pub status: u32,
    /// [`crate::mode::RejectCode`] when not OK.
    pub code: u32,
    /// Axis the reply concerns (1..6), 0 for none.
    pub axis: u32,
    /// Kind-specific figures, defined by [`crate::reply::Response::encode`] and `decode`.
    pub values: [f64; REPLY_VALUES],
}

/// The latest safety violation (or drive error), reported spontaneously to every client.
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
pub struct ErrorRecord {
    /// Increments with every new error; 0 = none since start.
    pub seq: u64,
    /// Cycle in which it tripped.
    pub cycle: u64,
    /// `CLOCK_REALTIME` of that cycle [ns since the Unix epoch]; names the flight-recorder file
    /// (see [`flight_recorder_file`]).
    pub unix_ns: u64,
    /// [`crate::mode::RejectCode`] naming the check.
    pub code: u32,
    /// Axis 1..6, 0 for none.
    pub axis: u32,
    /// The reason's figures, defined by [`crate::reply::SafetyError::encode`] and `decode`.
    pub values: [f64; 4],
}

/// Percentiles of the cycle's wake-up latency (how late the cycle thread woke after its
/// deadline) [ns], from a fixed-bucket histogram.
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
pub struct LatencyFigures {
    pub p50_ns: u64,
    pub p99_ns: u64,
    pub p99_9_ns: u64,
    pub p99_99_ns: u64,
    pub max_ns: u64,
    /// Cycles the figures are made of.
    pub cycles: u64,
}

/// Timing figures of the real-time cycle.
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
pub struct CycleTiming {
    /// Configured period [ns].
    pub period_ns: u64,
    /// Cycles that started later than their whole period.
    pub overruns: u64,
    /// Wake-up latency since start.
    pub since_start: LatencyFigures,
    /// Wake-up latency over the recent window (about the last `recent_window_ns`).
    pub recent: LatencyFigures,
    /// Span the recent figures cover [ns].
    pub recent_window_ns: u64,
    /// Longest time spent in one cycle's work (read, step, write, publish) [ns].
    pub work_max_ns: u64,
    /// Configured budget of one cycle's work [ns].
    pub work_budget_ns: u64,
    /// Cycles whose work took longer than `work_budget_ns`.
    pub over_budget: u64,
}

/// Counters of the CAN bus and of the CANopen master, since `mcm-rt` started. Each counts
/// something that should not happen: a value above 0 says frames were lost or garbled.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, ZeroCopySend)]
#[repr(C)]
pub struct BusCounters {
    /// Frames from configured nodes the master could not decode (wrong length, bad content).
    pub bad_frames: u64,
    /// Frames the master wanted to send that did not fit the cycle's frame buffer (not sent).
    pub frames_dropped: u64,
    /// Master events (drive lost, EMCY, ...) lost because the master's event ring was full.
    pub events_dropped: u64,
    /// Frames the bus refused to send or failed to receive (interface errors).
    pub bus_errors: u64,
}

/// The TCP's pose and velocity in the base frame, from the forward kinematics and the Jacobian
/// of the sample's own `position` and `velocity` (`docs/cartesian.md`). Valid when
/// [`STATE_CARTESIAN`] is set.
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
pub struct TcpState {
    /// The TCP's origin [m].
    pub position: [f64; 3],
    /// The TCP frame's orientation, a unit quaternion `[x, y, z, w]` with `w >= 0`.
    pub orientation: [f64; 4],
    /// The velocity of the TCP's origin [m/s].
    pub linear_velocity: [f64; 3],
    /// The TCP frame's angular velocity [deg/s].
    pub angular_velocity: [f64; 3],
}

/// The active tool ([`crate::tool::Tool`]) in a state sample: TCP [m, unit quaternion
/// `[x, y, z, w]`] in the flange frame, mass [kg], centre of mass [m], inertia
/// `[ixx, iyy, izz, ixy, ixz, iyz]` [kg m^2] about the centre of mass.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[repr(C)]
pub struct ToolState {
    pub tcp_position: [f64; 3],
    pub tcp_orientation: [f64; 4],
    pub mass: f64,
    pub center_of_mass: [f64; 3],
    pub inertia: [f64; 6],
}

impl Default for ToolState {
    /// No tool ([`Tool::NONE`]): the TCP on the flange, its quaternion of unit norm.
    fn default() -> ToolState {
        ToolState::from(&Tool::NONE)
    }
}

impl From<&Tool> for ToolState {
    fn from(t: &Tool) -> ToolState {
        ToolState {
            tcp_position: t.tcp.position,
            tcp_orientation: t.tcp.orientation,
            mass: t.mass,
            center_of_mass: t.center_of_mass,
            inertia: t.inertia,
        }
    }
}

impl From<&ToolState> for Tool {
    /// The tool as the core reports it (checked by the core when it took it).
    fn from(t: &ToolState) -> Tool {
        Tool {
            tcp: Tcp {
                position: t.tcp_position,
                orientation: t.tcp_orientation,
            },
            mass: t.mass,
            center_of_mass: t.center_of_mass,
            inertia: t.inertia,
        }
    }
}

/// The state of the arm and of the controller, published once per cycle.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("mcm.StateSample.v7")]
pub struct StateSample {
    /// Cycle counter (increments by one every cycle).
    pub seq: u64,
    /// `CLOCK_MONOTONIC` at the start of the cycle [ns].
    pub t_ns: u64,
    /// [`crate::mode::Mode`] as `u32`.
    pub mode: u32,
    /// `STATE_*` bits.
    pub flags: u32,
    /// Reported per the manual's notes: commanded in PVT and HOLD, measured otherwise [deg].
    pub position: [f64; NUM_AXES],
    /// [deg/s], same rule as `position`.
    pub velocity: [f64; NUM_AXES],
    /// [deg/s^2].
    pub acceleration: [f64; NUM_AXES],
    /// Motor currents [A]: measured in PVT and HOLD, commanded in RELEASE and TORQUE_CONTROL.
    pub current: [f64; NUM_AXES],
    /// Measured position [deg] (raw encoder position until calibrated).
    pub measured_position: [f64; NUM_AXES],
    /// Commanded position [deg].
    pub commanded_position: [f64; NUM_AXES],
    /// Commanded minus measured position [deg].
    pub following_error: [f64; NUM_AXES],
    /// i2t level per motor, 1.0 = threshold.
    pub i2t: [f64; NUM_AXES],
    /// Simulation ground truth: joint angles [deg] and velocities [deg/s].
    pub sim_true_position: [f64; NUM_AXES],
    pub sim_true_velocity: [f64; NUM_AXES],
    /// `AXIS_*` bits per axis.
    pub axis_flags: [u32; NUM_AXES],
    /// PVT queue: points queued and capacity.
    pub pvt_queued: u32,
    pub pvt_capacity: u32,
    /// Times receiving from the command service failed since start (each may have lost
    /// commands; the core goes on with the next cycle).
    pub command_receive_errors: u64,
    pub timing: CycleTiming,
    pub last_error: ErrorRecord,
    /// `seq` of the newest reply given (0 = none yet); see [`reply_location`] for where reply
    /// `n` is kept. Written after the replies, so every reply up to it is readable.
    pub reply_head: u64,
    /// The client that controls the arm's motion (0: none).
    pub owner_client_id: u64,
    /// The bus's and the CANopen master's error counters.
    pub bus: BusCounters,
    /// The TCP's state, when `flags` has [`STATE_CARTESIAN`].
    pub cartesian: TcpState,
    /// The active tool (`set_tool`; the configuration's `[arm.tool]` at start).
    pub tool: ToolState,
}

impl Default for StateSample {
    fn default() -> Self {
        Self {
            seq: 0,
            t_ns: 0,
            mode: 0,
            flags: 0,
            position: [0.0; NUM_AXES],
            velocity: [0.0; NUM_AXES],
            acceleration: [0.0; NUM_AXES],
            current: [0.0; NUM_AXES],
            measured_position: [0.0; NUM_AXES],
            commanded_position: [0.0; NUM_AXES],
            following_error: [0.0; NUM_AXES],
            i2t: [0.0; NUM_AXES],
            sim_true_position: [0.0; NUM_AXES],
            sim_true_velocity: [0.0; NUM_AXES],
            axis_flags: [0; NUM_AXES],
            pvt_queued: 0,
            pvt_capacity: 0,
            command_receive_errors: 0,
            timing: CycleTiming::default(),
            last_error: ErrorRecord::default(),
            reply_head: 0,
            owner_client_id: 0,
            bus: BusCounters::default(),
            cartesian: TcpState::default(),
            tool: ToolState::default(),
        }
    }
}

impl StateSample {
    /// The TCP's state, when the sample has one ([`STATE_CARTESIAN`]: every axis calibrated).
    pub fn tcp_state(&self) -> Option<&TcpState> {
        (self.flags & STATE_CARTESIAN != 0).then_some(&self.cartesian)
    }
}

/// One block of replies, the value of a reply key of the state blackboard.
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("mcm.ReplyBlock.v1")]
pub struct ReplyBlock {
    pub replies: [Reply; REPLY_BLOCK],
}

/// Where reply `seq` (1, 2, ...) is kept: its blackboard key (1 to [`REPLY_BLOCKS`]) and its
/// slot in that block. A reader finds it there while it is among the newest
/// `REPLY_BLOCKS * REPLY_BLOCK` replies; the slot's `seq` tells whether it was overwritten.
pub const fn reply_location(seq: u64) -> (u32, usize) {
    let n = seq.wrapping_sub(1);
    let block = (n / REPLY_BLOCK as u64) % REPLY_BLOCKS as u64;
    (block as u32 + 1, (n % REPLY_BLOCK as u64) as usize)
}

impl ReplyBlock {
    /// Reply `seq` if this block's slot for it still holds it (this must be the block
    /// [`reply_location`] names for `seq`); `None` when the slot was overwritten or not
    /// written yet.
    pub fn reply(&self, seq: u64) -> Option<&Reply> {
        let r = &self.replies[reply_location(seq).1];
        (r.seq == seq).then_some(r)
    }
}

/// A reader's handles of the reply blocks, in key order: the block of key `k` at `k - 1`.
pub type ReplyEntries = Vec<EntryHandle<ipc::Service, u32, ReplyBlock>>;

/// A reply-block entry of the state blackboard could not be opened (it is missing or of
/// another type: a core of another version).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("reply block {key}: {source}")]
pub struct ReplyEntryError {
    pub key: u32,
    #[source]
    pub source: EntryHandleError,
}

/// Open the reply blocks (keys 1 to [`REPLY_BLOCKS`]) of the state blackboard through `reader`.
pub fn open_reply_entries(
    reader: &Reader<ipc::Service, u32>,
) -> Result<ReplyEntries, ReplyEntryError> {
    (1..=REPLY_BLOCKS as u32)
        .map(|key| {
            reader
                .entry::<ReplyBlock>(&key)
                .map_err(|source| ReplyEntryError { key, source })
        })
        .collect()
}

/// Reply `seq` from the reply blocks [`open_reply_entries`] opened, if its slot still holds it
/// (`None`: overwritten since, or not written yet).
pub fn read_reply(
    entries: &[EntryHandle<ipc::Service, u32, ReplyBlock>],
    seq: u64,
) -> Option<Reply> {
    let (key, _) = reply_location(seq);
    entries[key as usize - 1].get().reply(seq).copied()
}

/// The flight-recorder file of an error: `<dir>/mcm-<instance>-<unix ms>-<check>.csv`. The
/// real-time core writes it; the gateway names it in the error message.
pub fn flight_recorder_file(dir: &str, instance: &str, e: &ErrorRecord) -> std::path::PathBuf {
    let check = crate::mode::RejectCode::try_from(e.code)
        .map(crate::mode::RejectCode::as_str)
        .unwrap_or("error");
    std::path::Path::new(dir).join(format!(
        "mcm-{instance}-{}-{check}.csv",
        e.unix_ns / 1_000_000
    ))
}

#[cfg(test)]
mod tests;
