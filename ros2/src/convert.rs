//! From the core's state to ROS messages: `/joint_states` and `/diagnostics`.
//!
//! Positions are the *measured* joint angles (raw encoder positions until an axis is
//! calibrated), as ros2_control's joint state broadcaster reports its state interfaces; the
//! velocity is their difference over one cycle (the core reports commanded velocities in PVT and
//! HOLD); the effort is the motor current times the axis's torque per ampere (measured in PVT
//! and HOLD, commanded in RELEASE and TORQUE_CONTROL, as the core's `current` is).

use crate::access::Access;
use crate::msgs::builtin::Time;
use crate::msgs::diagnostic::{DiagnosticArray, DiagnosticStatus, KeyValue, level};
use crate::msgs::sensor::JointState;
use crate::msgs::std_msgs::Header;
use mcm_shared::NUM_AXES;
use mcm_shared::busload::BusLoad;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::Mode;
use mcm_shared::reply::SafetyError;
use mcm_shared::sample::{
    AXIS_CALIBRATED, AXIS_ENABLED, AXIS_FAULT, AXIS_ONLINE, STATE_ALL_CALIBRATED, STATE_ESTOP,
    STATE_PVT_STARVED, StateSample,
};

/// Each of six degrees in radians.
pub fn rad6(deg: &[f64; NUM_AXES]) -> [f64; NUM_AXES] {
    deg.map(f64::to_radians)
}

/// Builds `/joint_states` from consecutive states (it keeps the previous measured position for
/// the velocity).
pub struct JointStates {
    names: Vec<String>,
    torque_per_amp: [f64; NUM_AXES],
    previous: Option<(u64, u64, [f64; NUM_AXES])>,
}

impl JointStates {
    pub fn new(names: Vec<String>, cfg: &RobotConfig) -> JointStates {
        let mut torque_per_amp = [0.0; NUM_AXES];
        for (t, a) in torque_per_amp.iter_mut().zip(&cfg.axes) {
            *t = a.torque_per_amp();
        }
        JointStates {
            names,
            torque_per_amp,
            previous: None,
        }
    }

    /// The measured velocity [rad/s] at `s`: the measured positions' difference over the time
    /// since the previous state (zero for the first).
    pub fn velocity(&mut self, s: &StateSample) -> [f64; NUM_AXES] {
        let q = rad6(&s.measured_position);
        let v = match self.previous {
            Some((seq, t_ns, prev)) if s.seq > seq && s.t_ns > t_ns => {
                let dt = (s.t_ns - t_ns) as f64 * 1e-9;
                std::array::from_fn(|i| (q[i] - prev[i]) / dt)
            }
            _ => [0.0; NUM_AXES],
        };
        self.previous = Some((s.seq, s.t_ns, q));
        v
    }

    /// The message for `s`, stamped `stamp`, with `velocity` from [`JointStates::velocity`].
    pub fn message(&self, s: &StateSample, velocity: [f64; NUM_AXES], stamp: Time) -> JointState {
        JointState {
            header: Header {
                stamp,
                frame_id: String::new(),
            },
            name: self.names.clone(),
            position: rad6(&s.measured_position).to_vec(),
            velocity: velocity.to_vec(),
            effort: (0..NUM_AXES)
                .map(|i| s.current[i] * self.torque_per_amp[i])
                .collect(),
        }
    }
}

/// What `/diagnostics` says about the MCM, besides the state.
pub struct DiagnosticsContext<'a> {
    /// `hardware_id`: the robot's name and instance.
    pub hardware_id: &'a str,
    /// This node's client id (to say whether it holds control).
    pub own_client_id: u64,
    /// The newest safety error the core reported since this node started.
    pub last_error: Option<&'a SafetyError>,
    pub bus: &'a BusLoad,
    /// `/joint_states` messages not published (states the node was too late for).
    pub missed_states: u64,
    /// `/joint_states` messages DDS did not take (a full send window).
    pub not_sent: u64,
    /// [`crate::driver::Driver::last_start_latency_cycles`].
    pub start_latency_cycles: Option<u64>,
    /// Whether the node offers its motion interface.
    pub access: Access,
}

/// One `DiagnosticStatus` named "mcm: <robot>" with the mode, calibration, errors, owner, the
/// cycle timing and the bus load.
pub fn diagnostics(s: &StateSample, cx: &DiagnosticsContext<'_>, stamp: Time) -> DiagnosticArray {
    let mode =
        Mode::try_from(s.mode).map_or_else(|_| format!("unknown ({})", s.mode), |m| m.to_string());
    let all_calibrated = s.flags & STATE_ALL_CALIBRATED != 0;
    let estop = s.flags & STATE_ESTOP != 0;
    let faults: Vec<usize> = (0..NUM_AXES)
        .filter(|&i| s.axis_flags[i] & AXIS_FAULT != 0)
        .map(|i| i + 1)
        .collect();
    let (lvl, message) = if s.mode == Mode::Error.to_wire() {
        let why = cx.last_error.map_or_else(
            || "a safety check tripped; call the hold service to clear it".to_string(),
            |e| e.to_string(),
        );
        (level::ERROR, format!("ERROR: {why}"))
    } else if estop {
        (level::ERROR, "emergency stop pressed".to_string())
    } else if !faults.is_empty() {
        (level::ERROR, format!("drive fault on axes {faults:?}"))
    } else if !all_calibrated {
        (
            level::WARN,
            format!("{mode}: not calibrated (call the calibrate service)"),
        )
    } else {
        (level::OK, mode.to_string())
    };
    let axes_with = |bit: u32| {
        (0..NUM_AXES)
            .filter(|&i| s.axis_flags[i] & bit != 0)
            .count()
            .to_string()
            + "/6"
    };
    let owner = owner_words(s.owner_client_id, cx.own_client_id);
    let t = &s.timing;
    let us = |ns: u64| format!("{:.1}", ns as f64 / 1e3);
    let values = vec![
        kv("mode", mode),
        kv("all calibrated", all_calibrated.to_string()),
        kv(
            "calibrated axes",
            (0..NUM_AXES)
                .map(|i| (s.axis_flags[i] & AXIS_CALIBRATED != 0).to_string())
                .collect::<Vec<_>>()
                .join(" "),
        ),
        kv("drives online", axes_with(AXIS_ONLINE)),
        kv("drives enabled", axes_with(AXIS_ENABLED)),
        kv("emergency stop", estop.to_string()),
        kv("owner", owner),
        kv(
            "motion interface",
            cx.access.diagnostics_value().to_string(),
        ),
        kv(
            "last error",
            cx.last_error
                .map_or_else(|| "none".to_string(), |e| e.to_string()),
        ),
        kv("cycle", s.seq.to_string()),
        kv("cycle period [us]", us(t.period_ns)),
        kv("wake-up latency p99 [us]", us(t.recent.p99_ns)),
        kv("wake-up latency max [us]", us(t.since_start.max_ns)),
        kv("work max [us]", us(t.work_max_ns)),
        kv("work budget [us]", us(t.work_budget_ns)),
        kv("over budget", t.over_budget.to_string()),
        kv("overruns", t.overruns.to_string()),
        kv("bad frames", s.bus.bad_frames.to_string()),
        kv("frames dropped", s.bus.frames_dropped.to_string()),
        kv("events dropped", s.bus.events_dropped.to_string()),
        kv("bus errors", s.bus.bus_errors.to_string()),
        kv("bus load [%]", format!("{:.1}", cx.bus.load * 100.0)),
        kv(
            "bus load budget [%]",
            format!("{:.1}", cx.bus.budget * 100.0),
        ),
        kv("pvt queue", format!("{}/{}", s.pvt_queued, s.pvt_capacity)),
        kv(
            "pvt starved",
            (s.flags & STATE_PVT_STARVED != 0).to_string(),
        ),
        kv("joint states missed", cx.missed_states.to_string()),
        kv("joint states not sent", cx.not_sent.to_string()),
        kv(
            "trajectory start latency [cycles]",
            cx.start_latency_cycles
                .map_or_else(|| "none yet".to_string(), |c| c.to_string()),
        ),
    ];
    DiagnosticArray {
        header: Header {
            stamp,
            frame_id: String::new(),
        },
        status: vec![DiagnosticStatus {
            level: lvl,
            name: format!("mcm: {}", cx.hardware_id),
            message,
            hardware_id: cx.hardware_id.to_string(),
            values,
        }],
    }
}

fn kv(key: &str, value: String) -> KeyValue {
    KeyValue {
        key: key.to_string(),
        value,
    }
}

/// Who a client id is, in words: this node, or the program whose process made it, e.g.
/// "client id 0x1a2b00000003 of mcm-gateway (pid 6699: a JSON, telnet, ZeroMQ or browser client
/// of the gateway; its `status` names the connection)".
pub fn owner_words(id: u64, own: u64) -> String {
    if id == 0 {
        return "nobody".to_string();
    }
    if id == own {
        return format!("this ROS 2 node (client id {id:#x})");
    }
    match mcm_client::shm::client_process(id) {
        Some((pid, p)) if p == "mcm-gateway" => format!(
            "client id {id:#x} of mcm-gateway (pid {pid}: a JSON, telnet, ZeroMQ or browser client of the gateway; its `status` names the connection)"
        ),
        Some((pid, p)) => format!("client id {id:#x} of {p} (pid {pid})"),
        None => format!("client id {id:#x} (pid {}, no longer running)", id >> 32),
    }
}
