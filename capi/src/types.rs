//! The C structs of the API and their conversions from the client's Rust types. The
//! conversion of the state ([`mcm_state_t`]) runs in the control loop: it copies, never
//! allocates.

use mcm_client::mcm_shared::sample::{
    BusCounters, CycleTiming, ErrorRecord, LatencyFigures, StateSample, TcpState,
};
use mcm_client::mcm_shared::tool::Tool;
use mcm_client::tcp::{
    CartesianState, Info, MoveAllResult, MoveLinearResult, PayloadResult, Pose, Status,
};
use std::ffi::c_char;

/// Axes of the arm (every per-axis array has this length; index 0 is axis 1).
pub const MCM_NUM_AXES: usize = 6;

/// `mcm_state_t.flags`: the emergency stop is pressed.
pub const MCM_STATE_ESTOP: u32 = 1;
/// `mcm_state_t.flags`: the robot is simulated (`sim_true_*` are the ground truth).
pub const MCM_STATE_SIMULATED: u32 = 1 << 1;
/// `mcm_state_t.flags`: every axis is calibrated.
pub const MCM_STATE_ALL_CALIBRATED: u32 = 1 << 2;
/// `mcm_state_t.flags`: the PVT queue ran dry while moving.
pub const MCM_STATE_PVT_STARVED: u32 = 1 << 3;
/// `mcm_state_t.flags`: the core runs without real-time scheduling.
pub const MCM_STATE_NOT_REALTIME: u32 = 1 << 4;
/// `mcm_state_t.flags`: the simulated emergency switch (ground truth).
pub const MCM_STATE_SIM_ESTOP: u32 = 1 << 5;
/// `mcm_state_t.flags`: the MCM is shutting down (every command but `status` is refused).
pub const MCM_STATE_SHUTTING_DOWN: u32 = 1 << 6;
/// `mcm_state_t.flags`: `cartesian` holds the TCP's state (every axis is calibrated); zeros
/// when clear.
pub const MCM_STATE_CARTESIAN: u32 = 1 << 7;
/// `mcm_state_t.axis_flags[i]`: the axis is calibrated.
pub const MCM_AXIS_CALIBRATED: u32 = 1;
/// `mcm_state_t.axis_flags[i]`: the drive answers on the bus.
pub const MCM_AXIS_ONLINE: u32 = 1 << 1;
/// `mcm_state_t.axis_flags[i]`: the drive is in Operation Enabled.
pub const MCM_AXIS_ENABLED: u32 = 1 << 2;
/// `mcm_state_t.axis_flags[i]`: the drive is in fault.
pub const MCM_AXIS_FAULT: u32 = 1 << 3;
/// `mcm_state_t.axis_flags[i]`: the motor current is derated by the i2t protection.
pub const MCM_AXIS_I2T_DERATED: u32 = 1 << 4;

/// Operating modes (`mcm_state_t.mode`, `mcm_status_t.mode`; `mcm_mode_name` names them).
pub const MCM_MODE_OFF: u32 = 0;
pub const MCM_MODE_ERROR: u32 = 1;
pub const MCM_MODE_HOLD: u32 = 2;
pub const MCM_MODE_RELEASE: u32 = 3;
pub const MCM_MODE_TORQUE_CONTROL: u32 = 4;
pub const MCM_MODE_PVT: u32 = 5;
pub const MCM_MODE_CALIBRATION: u32 = 6;
pub const MCM_MODE_VELOCITY_CONTROL: u32 = 7;

/// Wake-up latency percentiles of the real-time cycle [ns].
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_latency_t {
    pub p50_ns: u64,
    pub p99_ns: u64,
    pub p99_9_ns: u64,
    pub p99_99_ns: u64,
    pub max_ns: u64,
    /// Cycles the figures are made of.
    pub cycles: u64,
}

/// Timing figures of the real-time cycle.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_timing_t {
    /// Configured cycle period [ns].
    pub period_ns: u64,
    /// Cycles that started later than a whole period.
    pub overruns: u64,
    pub since_start: mcm_latency_t,
    pub recent: mcm_latency_t,
    /// Span of the recent window [ns].
    pub recent_window_ns: u64,
    /// Longest work of one cycle [ns].
    pub work_max_ns: u64,
    /// Budget of one cycle's work [ns].
    pub work_budget_ns: u64,
    /// Cycles over the budget.
    pub over_budget: u64,
}

/// Counters of the CAN bus and of the CANopen master since the core started; each counts
/// something that should not happen.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_bus_counters_t {
    /// Frames from configured nodes the master could not decode.
    pub bad_frames: u64,
    /// Frames that did not fit the cycle's frame buffer (not sent).
    pub frames_dropped: u64,
    /// Master events lost because the event ring was full.
    pub events_dropped: u64,
    /// Frames the bus refused to send or failed to receive.
    pub bus_errors: u64,
}

/// The newest safety error (or drive error) of the core.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_error_record_t {
    /// +1 with each error; 0: none since start.
    pub seq: u64,
    /// The cycle it tripped in.
    pub cycle: u64,
    /// `CLOCK_REALTIME` of that cycle [ns] (names the flight-recorder file).
    pub unix_ns: u64,
    /// The check, a reject code (`mcm_reject_name`).
    pub code: u32,
    /// Axis 1 to 6, 0 for none.
    pub axis: u32,
    /// The check's figures (docs/clients.md, "Reject codes and their figures").
    pub values: [f64; 4],
}

/// The TCP's pose and velocity in the base frame (docs/cartesian.md), from the same axis
/// values as the state or status it comes with.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_tcp_state_t {
    /// The TCP's origin [m].
    pub position: [f64; 3],
    /// The TCP frame's orientation, a unit quaternion [x, y, z, w] (w >= 0).
    pub orientation: [f64; 4],
    /// [m/s]
    pub linear_velocity: [f64; 3],
    /// [deg/s]
    pub angular_velocity: [f64; 3],
}

/// The state of one cycle, as the real-time core publishes it (the shared-memory
/// `StateSample`, field for field; units: deg, deg/s, deg/s^2, A, ns).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_state_t {
    /// Cycle counter k, +1 every cycle.
    pub seq: u64,
    /// `CLOCK_MONOTONIC` at the start of the cycle [ns].
    pub t_ns: u64,
    /// Operating mode (`MCM_MODE_*`).
    pub mode: u32,
    /// `MCM_STATE_*` bits.
    pub flags: u32,
    /// Commanded in PVT and HOLD, measured otherwise [deg].
    pub position: [f64; MCM_NUM_AXES],
    /// Same rule as `position` [deg/s].
    pub velocity: [f64; MCM_NUM_AXES],
    /// [deg/s^2]
    pub acceleration: [f64; MCM_NUM_AXES],
    /// Motor currents [A].
    pub current: [f64; MCM_NUM_AXES],
    /// From the encoders [deg] (raw until calibrated).
    pub measured_position: [f64; MCM_NUM_AXES],
    /// [deg]
    pub commanded_position: [f64; MCM_NUM_AXES],
    /// Commanded minus measured [deg].
    pub following_error: [f64; MCM_NUM_AXES],
    /// i2t level per motor, 1.0 = threshold.
    pub i2t: [f64; MCM_NUM_AXES],
    /// Simulation only: the true joint angles [deg] and velocities [deg/s].
    pub sim_true_position: [f64; MCM_NUM_AXES],
    pub sim_true_velocity: [f64; MCM_NUM_AXES],
    /// `MCM_AXIS_*` bits per axis.
    pub axis_flags: [u32; MCM_NUM_AXES],
    /// PVT points queued, and the queue's capacity.
    pub pvt_queued: u32,
    pub pvt_capacity: u32,
    /// Failed receives from the command service since start.
    pub command_receive_errors: u64,
    pub timing: mcm_timing_t,
    pub last_error: mcm_error_record_t,
    /// Number of the newest reply.
    pub reply_head: u64,
    /// The client that controls the arm (0: nobody; compare with `mcm_shm_client_id`).
    pub owner_client_id: u64,
    /// The bus's and the CANopen master's error counters.
    pub bus: mcm_bus_counters_t,
    /// The TCP's state, when `flags` has `MCM_STATE_CARTESIAN`.
    pub cartesian: mcm_tcp_state_t,
    /// The active tool (`set_tool`; the configuration's at start).
    pub tool: mcm_tool_t,
}

fn latency(l: &LatencyFigures) -> mcm_latency_t {
    mcm_latency_t {
        p50_ns: l.p50_ns,
        p99_ns: l.p99_ns,
        p99_9_ns: l.p99_9_ns,
        p99_99_ns: l.p99_99_ns,
        max_ns: l.max_ns,
        cycles: l.cycles,
    }
}

fn timing(t: &CycleTiming) -> mcm_timing_t {
    mcm_timing_t {
        period_ns: t.period_ns,
        overruns: t.overruns,
        since_start: latency(&t.since_start),
        recent: latency(&t.recent),
        recent_window_ns: t.recent_window_ns,
        work_max_ns: t.work_max_ns,
        work_budget_ns: t.work_budget_ns,
        over_budget: t.over_budget,
    }
}

fn bus_counters(b: &BusCounters) -> mcm_bus_counters_t {
    mcm_bus_counters_t {
        bad_frames: b.bad_frames,
        frames_dropped: b.frames_dropped,
        events_dropped: b.events_dropped,
        bus_errors: b.bus_errors,
    }
}

fn tcp_state(t: &TcpState) -> mcm_tcp_state_t {
    mcm_tcp_state_t {
        position: t.position,
        orientation: t.orientation,
        linear_velocity: t.linear_velocity,
        angular_velocity: t.angular_velocity,
    }
}

impl From<&CartesianState> for mcm_tcp_state_t {
    fn from(t: &CartesianState) -> mcm_tcp_state_t {
        mcm_tcp_state_t {
            position: t.position,
            orientation: t.orientation,
            linear_velocity: t.linear_velocity,
            angular_velocity: t.angular_velocity,
        }
    }
}

fn error_record(e: &ErrorRecord) -> mcm_error_record_t {
    mcm_error_record_t {
        seq: e.seq,
        cycle: e.cycle,
        unix_ns: e.unix_ns,
        code: e.code,
        axis: e.axis,
        values: e.values,
    }
}

impl From<&StateSample> for mcm_state_t {
    fn from(s: &StateSample) -> mcm_state_t {
        mcm_state_t {
            seq: s.seq,
            t_ns: s.t_ns,
            mode: s.mode,
            flags: s.flags,
            position: s.position,
            velocity: s.velocity,
            acceleration: s.acceleration,
            current: s.current,
            measured_position: s.measured_position,
            commanded_position: s.commanded_position,
            following_error: s.following_error,
            i2t: s.i2t,
            sim_true_position: s.sim_true_position,
            sim_true_velocity: s.sim_true_velocity,
            axis_flags: s.axis_flags,
            pvt_queued: s.pvt_queued,
            pvt_capacity: s.pvt_capacity,
            command_receive_errors: s.command_receive_errors,
            timing: timing(&s.timing),
            last_error: error_record(&s.last_error),
            reply_head: s.reply_head,
            owner_client_id: s.owner_client_id,
            bus: bus_counters(&s.bus),
            cartesian: tcp_state(&s.cartesian),
            tool: (&Tool::from(&s.tool)).into(),
        }
    }
}

/// The answer to `status` over TCP (and to `hold`, `release`, `pvt`, `torque_control`,
/// `velocity_control`; the status events of a torque or velocity session).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_status_t {
    /// Operating mode (`MCM_MODE_*`).
    pub mode: u32,
    /// The cycle's time [s] (`CLOCK_MONOTONIC` of the robot's computer).
    pub time: f64,
    /// [deg]
    pub position: [f64; MCM_NUM_AXES],
    /// [deg/s]
    pub velocity: [f64; MCM_NUM_AXES],
    /// [deg/s^2]
    pub acceleration: [f64; MCM_NUM_AXES],
    /// [A]
    pub current: [f64; MCM_NUM_AXES],
    /// `cartesian` is set (every axis is calibrated); false: it is zero.
    pub has_cartesian: bool,
    /// The TCP's state (`cartesian_state`).
    pub cartesian: mcm_tcp_state_t,
    /// The fields below are set (by `mcm_tcp_status_detail`); false: they are zero.
    pub has_detail: bool,
    /// Cycle counter.
    pub cycle: u64,
    pub calibrated: [bool; MCM_NUM_AXES],
    pub all_calibrated: bool,
    pub emergency_stop: bool,
    /// [deg]
    pub measured_position: [f64; MCM_NUM_AXES],
    pub commanded_position: [f64; MCM_NUM_AXES],
    pub following_error: [f64; MCM_NUM_AXES],
    pub pvt_queued: u32,
    pub pvt_capacity: u32,
    pub pvt_starved: bool,
    /// The active tool (`detail.tool`: `set_tool`, the configuration's at start).
    pub tool: mcm_tool_t,
}

impl From<&Status> for mcm_status_t {
    fn from(s: &Status) -> mcm_status_t {
        let a = &s.axis_states;
        let mut out = mcm_status_t {
            mode: s.mode.to_wire(),
            time: s.time(),
            position: a.position,
            velocity: a.velocity,
            acceleration: a.acceleration,
            current: a.current,
            ..Default::default()
        };
        if let Some(c) = &s.cartesian_state {
            out.has_cartesian = true;
            out.cartesian = c.into();
        }
        if let Some(d) = &s.detail {
            out.has_detail = true;
            out.cycle = d.cycle;
            out.calibrated = d.calibrated;
            out.all_calibrated = d.all_calibrated;
            out.emergency_stop = d.emergency_stop;
            out.measured_position = d.measured_position;
            out.commanded_position = d.commanded_position;
            out.following_error = d.following_error;
            out.pvt_queued = d.pvt_queue.queued;
            out.pvt_capacity = d.pvt_queue.capacity;
            out.pvt_starved = d.pvt_queue.starved;
            out.tool = (&d.tool).into();
        }
        out
    }
}

/// Limits of one axis (from `info` over TCP).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct mcm_axis_info_t {
    /// 1 to 6.
    pub axis: u32,
    /// NUL-terminated (cut to fit).
    pub name: [c_char; 32],
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

/// The answer to `info` over TCP.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct mcm_info_t {
    pub num_axes: u32,
    /// Cycle period [s].
    pub cycle_time: f64,
    pub simulated: bool,
    /// NUL-terminated (cut to fit), e.g. "0.1.0".
    pub version: [c_char; 32],
    /// NUL-terminated (cut to fit), e.g. "P-Rob2".
    pub robot: [c_char; 64],
    /// The first `num_axes` are set.
    pub axes: [mcm_axis_info_t; MCM_NUM_AXES],
}

/// Copy `s` into `buf` as a NUL-terminated string, cut to fit.
fn fill<const N: usize>(buf: &mut [c_char; N], s: &str) {
    *buf = [0; N];
    for (d, b) in buf.iter_mut().zip(s.bytes().take(N - 1)) {
        *d = b as c_char;
    }
}

impl From<&Info> for mcm_info_t {
    fn from(i: &Info) -> mcm_info_t {
        let blank = mcm_axis_info_t {
            axis: 0,
            name: [0; 32],
            min_position: 0.0,
            max_position: 0.0,
            max_velocity: 0.0,
            max_acceleration: 0.0,
            max_torque: 0.0,
            light_barrier: false,
        };
        let mut out = mcm_info_t {
            num_axes: i.num_axes,
            cycle_time: i.cycle_time,
            simulated: i.simulated,
            version: [0; 32],
            robot: [0; 64],
            axes: [blank; MCM_NUM_AXES],
        };
        fill(&mut out.version, &i.version);
        fill(&mut out.robot, &i.robot);
        for (o, a) in out.axes.iter_mut().zip(&i.axes) {
            o.axis = u32::from(a.axis);
            fill(&mut o.name, &a.name);
            o.min_position = a.min_position;
            o.max_position = a.max_position;
            o.max_velocity = a.max_velocity;
            o.max_acceleration = a.max_acceleration;
            o.max_torque = a.max_torque;
            o.light_barrier = a.light_barrier;
        }
        out
    }
}

/// The answer to `info` over shared memory.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_shm_info_t {
    pub num_axes: u32,
    /// Cycle period [s].
    pub period_s: f64,
}

/// The move `move_all` planned.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_move_all_result_t {
    /// Peak velocity of each axis [deg/s].
    pub velocities: [f64; MCM_NUM_AXES],
    /// The axis (1 to 6) that would take longest on its own.
    pub longest: u32,
    /// Time from now to the target [s].
    pub max_time_to_target: f64,
}

impl From<&MoveAllResult> for mcm_move_all_result_t {
    fn from(r: &MoveAllResult) -> Self {
        mcm_move_all_result_t {
            velocities: r.velocities,
            longest: u32::from(r.longest),
            max_time_to_target: r.max_time_to_target,
        }
    }
}

impl From<&mcm_client::mcm_shared::reply::MoveAllPlan> for mcm_move_all_result_t {
    fn from(p: &mcm_client::mcm_shared::reply::MoveAllPlan) -> Self {
        mcm_move_all_result_t {
            velocities: p.velocities_deg_s,
            longest: u32::from(p.longest.number()),
            max_time_to_target: p.duration_s,
        }
    }
}

/// The load `identify_payload` estimated.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_payload_t {
    /// [kg]
    pub mass: f64,
    /// Flange frame [m] (zeros for a load below 0.05 kg).
    pub center_of_mass: [f64; 3],
    /// RMS over every axis and pose of the holding torque the estimate does not explain [N m].
    pub residual: f64,
}

impl From<&PayloadResult> for mcm_payload_t {
    fn from(r: &PayloadResult) -> Self {
        mcm_payload_t {
            mass: r.mass,
            center_of_mass: r.center_of_mass,
            residual: r.residual,
        }
    }
}

/// A straight line of the TCP as `move_linear` takes it, in the base frame. A zeroed one keeps
/// the orientation and takes the MCM's default speed and acceleration.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_move_linear_t {
    /// The TCP's target position [m].
    pub position: [f64; 3],
    /// The TCP's target orientation, a unit quaternion `[x, y, z, w]` (with
    /// `has_orientation`).
    pub orientation: [f64; 4],
    /// `orientation` is given; false: the present orientation is kept.
    pub has_orientation: bool,
    /// The TCP's speed [m/s], from 0.001 to 1; 0: the default (0.25).
    pub velocity: f64,
    /// The TCP's acceleration [m/s^2], from 0.01 to 10; 0: the default (1.2).
    pub acceleration: f64,
}

/// The line `move_linear` planned.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_move_linear_result_t {
    /// Time from now to the target [s].
    pub duration: f64,
    /// Each axis's position at the target [deg].
    pub joint_target: [f64; MCM_NUM_AXES],
}

impl From<&MoveLinearResult> for mcm_move_linear_result_t {
    fn from(r: &MoveLinearResult) -> Self {
        mcm_move_linear_result_t {
            duration: r.duration,
            joint_target: r.joint_target,
        }
    }
}

impl From<&mcm_client::mcm_shared::reply::PayloadReply> for mcm_payload_t {
    fn from(p: &mcm_client::mcm_shared::reply::PayloadReply) -> Self {
        mcm_payload_t {
            mass: p.mass_kg,
            center_of_mass: p.center_of_mass_m,
            residual: p.residual_nm,
        }
    }
}

impl From<&mcm_client::mcm_shared::reply::MoveLinearPlan> for mcm_move_linear_result_t {
    fn from(p: &mcm_client::mcm_shared::reply::MoveLinearPlan) -> Self {
        mcm_move_linear_result_t {
            duration: p.duration_s,
            joint_target: p.joint_target_deg,
        }
    }
}

impl From<&mcm_client::mcm_shared::reply::InfoReply> for mcm_shm_info_t {
    fn from(i: &mcm_client::mcm_shared::reply::InfoReply) -> Self {
        mcm_shm_info_t {
            num_axes: i.num_axes,
            period_s: i.period_s,
        }
    }
}

/// Options of `calibrate` (NULL: all axes, default directions, light barriers where the axis
/// has one).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_calibrate_t {
    /// 0: all axes; 1 to 6: that axis; 7: the elbow (axes 1 to 3); 8: the wrist (4 to 6).
    pub which: u32,
    /// +1 (or 0): the default direction; -1: the reverse one.
    pub elbow_direction: i32,
    pub wrist_direction: i32,
    /// Use the mechanical stops even where light barriers exist.
    pub force_mechanical_stop: bool,
}

/// Options of `torque_control` and `velocity_control` (`mcm_control_options_default` gives
/// the protocol's defaults).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct mcm_control_options_t {
    /// Fall back to HOLD when no `set_torques` (`set_velocities`) came for this long [s];
    /// negative: never (0 is refused by the MCM).
    pub timeout_s: f64,
    /// TCP only: interval of the status events [s] (`mcm_tcp_next_event`); 0: none.
    pub dt_status_s: f64,
    /// `torque_control` only: add the model's gravity (and 70 % of its friction) compensation.
    pub gravity_compensation: bool,
}

/// The protocol's defaults: timeout 1 s, no status events, gravity compensated.
#[unsafe(no_mangle)]
pub extern "C" fn mcm_control_options_default() -> mcm_control_options_t {
    mcm_control_options_t {
        timeout_s: 1.0,
        dt_status_s: 0.0,
        gravity_compensation: true,
    }
}

/// One point of a PVT stream.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_pvt_point_t {
    /// [deg]
    pub position: [f64; MCM_NUM_AXES],
    /// [deg/s]
    pub velocity: [f64; MCM_NUM_AXES],
}

impl From<&mcm_pvt_point_t> for mcm_client::PvtPoint {
    fn from(p: &mcm_pvt_point_t) -> Self {
        mcm_client::PvtPoint {
            position_deg: p.position,
            velocity_deg_s: p.velocity,
        }
    }
}

/// A tool as `set_tool` takes it: the TCP in the flange frame, the load.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_tool_t {
    /// The TCP's position in the flange frame [m].
    pub tcp_position: [f64; 3],
    /// The TCP's orientation in the flange frame, a unit quaternion `[x, y, z, w]`.
    pub tcp_orientation: [f64; 4],
    /// [kg], from 0 to 5.
    pub mass: f64,
    /// In the flange frame [m].
    pub center_of_mass: [f64; 3],
    /// `[ixx, iyy, izz, ixy, ixz, iyz]` about the centre of mass [kg m^2]; zeros: a point
    /// mass.
    pub inertia: [f64; 6],
}

impl From<&Tool> for mcm_tool_t {
    fn from(t: &Tool) -> Self {
        mcm_tool_t {
            tcp_position: t.tcp.position,
            tcp_orientation: t.tcp.orientation,
            mass: t.mass,
            center_of_mass: t.center_of_mass,
            inertia: t.inertia,
        }
    }
}

/// A pose of the TCP in the base frame, as `inverse_kinematics` and `move_to_pose` take it
/// (docs/cartesian.md).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_pose_t {
    /// [m]
    pub position: [f64; 3],
    /// A unit quaternion [x, y, z, w] (the MCM normalises one whose norm is within 0.001 of
    /// 1 and refuses any other).
    pub orientation: [f64; 4],
}

impl From<&mcm_pose_t> for Pose {
    fn from(p: &mcm_pose_t) -> Pose {
        Pose {
            position: p.position,
            orientation: p.orientation,
        }
    }
}

/// The most solutions `inverse_kinematics` answers (shoulder, elbow and wrist each on one
/// side or the other).
pub const MCM_MAX_IK_SOLUTIONS: usize = 8;

/// The answer to `inverse_kinematics`: every joint configuration that puts the TCP at the
/// pose, within the axis limits, the nearest to the seed first.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_ik_solutions_t {
    /// The solutions set, 1 to `MCM_MAX_IK_SOLUTIONS` (a pose without one is refused).
    pub count: u32,
    /// The first `count` are set [deg]; the rest are zero.
    pub solutions: [[f64; MCM_NUM_AXES]; MCM_MAX_IK_SOLUTIONS],
}

/// `mcm_event_t.kind`: a status of this connection's torque or velocity session (TCP).
pub const MCM_EVENT_STATUS: u32 = 1;
/// `mcm_event_t.kind`: a safety check tripped (`code` names it, `axis` the axis).
pub const MCM_EVENT_SAFETY_ERROR: u32 = 2;
/// `mcm_event_t.kind`: a command sent without waiting (`set_torques`, `set_velocities`, a
/// control loop's command) was refused.
pub const MCM_EVENT_COMMAND_ERROR: u32 = 3;
/// `mcm_event_t.kind`: a notice (TCP: shutting down, connection closed; shared memory: a
/// safety error record this library cannot read).
pub const MCM_EVENT_NOTICE: u32 = 4;

/// Something the MCM reported that answers no call.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct mcm_event_t {
    /// `MCM_EVENT_*`.
    pub kind: u32,
    /// Error code (`mcm_error_code_t`, `mcm_error_code_name`), 0: none.
    pub code: u32,
    /// Axis 1 to 6, 0: none.
    pub axis: u32,
    /// The MCM's words, NUL-terminated; owned by the handle, valid until its next call.
    pub message: *const c_char,
    /// `MCM_EVENT_STATUS` only: the status.
    pub status: mcm_status_t,
}

/// What a control loop did (`mcm_shm_control`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_control_summary_t {
    /// States the callback was called with.
    pub cycles: u64,
    /// Cycles whose state the callback never saw (the loop was late).
    pub missed: u64,
    /// Commands sent.
    pub sent: u64,
    /// Answers to the state of cycle k applied by the core in cycle k + 1.
    pub on_time: u64,
    /// Answers applied later.
    pub late: u64,
    /// Commands whose reply was not read before the loop ended.
    pub unanswered: u64,
}

impl From<&mcm_client::shm::ControlSummary> for mcm_control_summary_t {
    fn from(s: &mcm_client::shm::ControlSummary) -> Self {
        mcm_control_summary_t {
            cycles: s.cycles,
            missed: s.missed,
            sent: s.sent,
            on_time: s.on_time,
            late: s.late,
            unanswered: s.unanswered,
        }
    }
}

/// `mcm_control_output_t.kind`: `values` are torques [Nm] (TORQUE_CONTROL).
pub const MCM_OUTPUT_TORQUES: u32 = 1;
/// `mcm_control_output_t.kind`: `values` are velocities [deg/s] (VELOCITY_CONTROL).
pub const MCM_OUTPUT_VELOCITIES: u32 = 2;
/// `mcm_control_output_t.kind`: `values` are positions [deg] and `pvt_velocities` velocities
/// [deg/s] of the next PVT point (PVT, `dt` one cycle).
pub const MCM_OUTPUT_PVT: u32 = 3;

/// What a control callback answers a state with. The loop sets `kind` from the mode it runs in
/// and zeroes the values before each call; the callback fills `values` (and for PVT
/// `pvt_velocities`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct mcm_control_output_t {
    /// `MCM_OUTPUT_*`.
    pub kind: u32,
    pub values: [f64; MCM_NUM_AXES],
    pub pvt_velocities: [f64; MCM_NUM_AXES],
}

/// A control callback's answer: go on with the next cycle.
pub const MCM_CONTROL_CONTINUE: i32 = 0;
/// A control callback's answer (any value but 0): end the loop; nothing is sent for this state.
pub const MCM_CONTROL_FINISH: i32 = 1;

/// The control loop's callback: called with each cycle's state, fills `out`, returns
/// `MCM_CONTROL_CONTINUE` or `MCM_CONTROL_FINISH`. It runs on the loop's thread and must not
/// call functions of the same handle. It must return within the cycle (5 ms on the P-Rob2,
/// less the wake-up) for its answer to be applied in the next cycle; C++ exceptions must not
/// leave it (`mcm.hpp` catches them).
pub type mcm_control_fn = Option<
    unsafe extern "C" fn(
        state: *const mcm_state_t,
        out: *mut mcm_control_output_t,
        user: *mut std::ffi::c_void,
    ) -> i32,
>;

/// A `wait_until` condition over shared memory: nonzero when the state shows what is waited
/// for.
pub type mcm_state_predicate_fn =
    Option<unsafe extern "C" fn(state: *const mcm_state_t, user: *mut std::ffi::c_void) -> i32>;

/// A `wait_until` condition over TCP: nonzero when the status shows what is waited for.
pub type mcm_status_predicate_fn =
    Option<unsafe extern "C" fn(status: *const mcm_status_t, user: *mut std::ffi::c_void) -> i32>;

#[cfg(test)]
mod tests;
