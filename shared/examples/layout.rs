//! Prints the layouts of the shared-memory samples as JSON: for each struct its iceoryx2 type
//! name, size, alignment and the offset of every field, as the Rust compiler laid them out.
//! Clients in other languages check their mirrors against it (the Python package's ctypes
//! structures: `tests/end_to_end/python_layout.rs` includes this file and runs the Python check).
//!
//! ```sh
//! cargo run -p mcm-shared --example layout
//! ```

use core::mem::{align_of, offset_of, size_of};
use iceoryx2::prelude::ZeroCopySend;
use mcm_shared::sample::{
    BusCounters, CommandSample, CycleTiming, ErrorRecord, LatencyFigures, Reply, ReplyBlock,
    StateSample, TcpState, ToolState,
};

/// One struct's layout: its name, the iceoryx2 type name (`None` for a struct that is only
/// ever a field of another), size, alignment and `(field, offset)` in declaration order.
struct Layout {
    name: &'static str,
    type_name: Option<&'static str>,
    size: usize,
    align: usize,
    fields: Vec<(&'static str, usize)>,
}

/// The iceoryx2 type name of `T` (what a peer opening a service must present).
fn type_name<T: ZeroCopySend>() -> &'static str {
    // SAFETY: `type_name` only returns the name given with `#[type_name]` (or Rust's own type
    // name); the caller merely prints it, so the layout guarantee the trait demands from
    // implementors is not relied upon here.
    unsafe { <T as ZeroCopySend>::type_name() }
}

macro_rules! layout {
    ($t:ty, $type_name:expr, [$($f:ident),* $(,)?]) => {
        Layout {
            name: stringify!($t),
            type_name: $type_name,
            size: size_of::<$t>(),
            align: align_of::<$t>(),
            fields: vec![$((stringify!($f), offset_of!($t, $f))),*],
        }
    };
}

/// Every shared-memory struct's layout.
fn layouts() -> Vec<Layout> {
    vec![
        layout!(
            CommandSample,
            Some(type_name::<CommandSample>()),
            [client_id, request_id, kind, flags, args]
        ),
        layout!(
            Reply,
            None,
            [
                seq, client_id, request_id, cycle, kind, status, code, axis, values
            ]
        ),
        layout!(ErrorRecord, None, [seq, cycle, unix_ns, code, axis, values]),
        layout!(
            LatencyFigures,
            None,
            [p50_ns, p99_ns, p99_9_ns, p99_99_ns, max_ns, cycles]
        ),
        layout!(
            CycleTiming,
            None,
            [
                period_ns,
                overruns,
                since_start,
                recent,
                recent_window_ns,
                work_max_ns,
                work_budget_ns,
                over_budget
            ]
        ),
        layout!(
            BusCounters,
            None,
            [bad_frames, frames_dropped, events_dropped, bus_errors]
        ),
        layout!(
            TcpState,
            None,
            [position, orientation, linear_velocity, angular_velocity]
        ),
        layout!(
            ToolState,
            None,
            [tcp_position, tcp_orientation, mass, center_of_mass, inertia]
        ),
        layout!(
            StateSample,
            Some(type_name::<StateSample>()),
            [
                seq,
                t_ns,
                mode,
                flags,
                position,
                velocity,
                acceleration,
                current,
                measured_position,
                commanded_position,
                following_error,
                i2t,
                sim_true_position,
                sim_true_velocity,
                axis_flags,
                pvt_queued,
                pvt_capacity,
                command_receive_errors,
                timing,
                last_error,
                reply_head,
                owner_client_id,
                bus,
                cartesian,
                tool
            ]
        ),
        layout!(ReplyBlock, Some(type_name::<ReplyBlock>()), [replies]),
    ]
}

/// The wire codes as JSON members: `"modes"` and `"kinds"` (protocol name: wire value),
/// `"needs_control"` (the kinds only the controlling client may send) and `"reject_codes"`,
/// so that a client's copy of them (the Python package's `codes.py`) cannot drift.
fn codes_json() -> String {
    use mcm_shared::mode::{CommandKind, Mode, RejectCode};
    fn table<T: Copy>(all: &[T], name: fn(T) -> &'static str, wire: fn(T) -> u32) -> String {
        let rows: Vec<String> = all
            .iter()
            .map(|&x| format!("\"{}\": {}", name(x), wire(x)))
            .collect();
        format!("{{{}}}", rows.join(", "))
    }
    let needs: Vec<String> = CommandKind::ALL
        .iter()
        .filter(|k| k.needs_control())
        .map(|k| format!("\"{}\"", k.as_str()))
        .collect();
    format!(
        "\"modes\": {}, \"kinds\": {}, \"needs_control\": [{}], \"reject_codes\": {}",
        table(Mode::ALL, Mode::as_str, Mode::to_wire),
        table(CommandKind::ALL, CommandKind::as_str, CommandKind::to_wire),
        needs.join(", "),
        table(RejectCode::ALL, RejectCode::as_str, RejectCode::to_wire)
    )
}

/// The layouts as one JSON object: `{"structs": {NAME: {"type_name", "size", "align",
/// "fields": {FIELD: OFFSET}}}, "constants": {...}, "reply_locations": [...], "reasons":
/// [...], "commands": [...]}` and the wire codes of [`codes_json`]. Field order is declaration
/// order.
pub fn layout_json() -> String {
    use mcm_shared::sample as s;
    use mcm_shared::service as v;
    let structs: Vec<String> = layouts()
        .iter()
        .map(|l| {
            let fields: Vec<String> = l
                .fields
                .iter()
                .map(|(f, o)| format!("\"{f}\": {o}"))
                .collect();
            let type_name = l
                .type_name
                .map_or("null".to_string(), |t| format!("\"{t}\""));
            format!(
                "\"{}\": {{\"type_name\": {type_name}, \"size\": {}, \"align\": {}, \"fields\": {{{}}}}}",
                l.name,
                l.size,
                l.align,
                fields.join(", ")
            )
        })
        .collect();
    let constants = [
        ("NUM_AXES", mcm_shared::NUM_AXES as u64),
        ("COMMAND_ARGS", s::COMMAND_ARGS as u64),
        ("PVT_POINTS_PER_COMMAND", s::PVT_POINTS_PER_COMMAND as u64),
        ("REPLY_BLOCK", s::REPLY_BLOCK as u64),
        ("REPLY_BLOCKS", s::REPLY_BLOCKS as u64),
        ("REPLY_VALUES", s::REPLY_VALUES as u64),
        ("STATE_KEY", u64::from(v::STATE_KEY)),
        ("STATE_EVENT_ID", v::STATE_EVENT_ID as u64),
        ("COMMAND_BUFFER", v::COMMAND_BUFFER as u64),
        ("PVT_FLAG_LAST", u64::from(s::PVT_FLAG_LAST)),
        (
            "TORQUE_FLAG_NO_GRAVITY",
            u64::from(s::TORQUE_FLAG_NO_GRAVITY),
        ),
        (
            "CALIBRATE_FLAG_FORCE_STOP",
            u64::from(s::CALIBRATE_FLAG_FORCE_STOP),
        ),
        ("IDENTIFY_FLAG_APPLY", u64::from(s::IDENTIFY_FLAG_APPLY)),
        ("SIM_FLAG_POWER_CYCLE", u64::from(s::SIM_FLAG_POWER_CYCLE)),
        ("STATE_ESTOP", u64::from(s::STATE_ESTOP)),
        ("STATE_SIMULATED", u64::from(s::STATE_SIMULATED)),
        ("STATE_ALL_CALIBRATED", u64::from(s::STATE_ALL_CALIBRATED)),
        ("STATE_PVT_STARVED", u64::from(s::STATE_PVT_STARVED)),
        ("STATE_NOT_REALTIME", u64::from(s::STATE_NOT_REALTIME)),
        ("STATE_SIM_ESTOP", u64::from(s::STATE_SIM_ESTOP)),
        ("STATE_SHUTTING_DOWN", u64::from(s::STATE_SHUTTING_DOWN)),
        ("STATE_CARTESIAN", u64::from(s::STATE_CARTESIAN)),
        ("AXIS_CALIBRATED", u64::from(s::AXIS_CALIBRATED)),
        ("AXIS_ONLINE", u64::from(s::AXIS_ONLINE)),
        ("AXIS_ENABLED", u64::from(s::AXIS_ENABLED)),
        ("AXIS_FAULT", u64::from(s::AXIS_FAULT)),
        ("AXIS_I2T_DERATED", u64::from(s::AXIS_I2T_DERATED)),
    ]
    .map(|(k, v)| format!("\"{k}\": {v}"));
    // Reply locations at the edges of the ring, for the Python port of `reply_location`.
    let ring = (s::REPLY_BLOCKS * s::REPLY_BLOCK) as u64;
    let locations: Vec<String> = [1, 2, 16, 17, ring, ring + 1, 7 * ring + 3]
        .iter()
        .map(|&seq| {
            let (key, slot) = s::reply_location(seq);
            format!("[{seq}, {key}, {slot}]")
        })
        .collect();
    format!(
        "{{\"structs\": {{{}}}, \"constants\": {{{}}}, \"reply_locations\": [{}], \"reasons\": [{}], \"commands\": [{}], {}}}",
        structs.join(", "),
        constants.join(", "),
        locations.join(", "),
        reasons().join(", "),
        encoded_commands().join(", "),
        codes_json()
    )
}

/// Reasons as they travel (code, axis, values) and the words the core gives for them, so that
/// a client's port of `Reason`'s `Display` can be checked: `[code, axis, [v0..v3], "text"]`.
fn reasons() -> Vec<String> {
    use mcm_shared::command::Axis;
    use mcm_shared::mode::Mode;
    use mcm_shared::reply::{CalibrationFailure, LineFault, PvtQuantity, Reason, Singularity};
    let a = |n| Axis::new(n).expect("axis 1..6");
    [
        Reason::WrongMode { mode: Mode::Hold },
        Reason::NotCalibrated { axis: a(3) },
        Reason::EmergencyStop,
        Reason::DriveDisconnected {
            axis: a(2),
            also: 0,
        },
        Reason::DriveDisconnected {
            axis: a(1),
            also: 0b11_1110,
        },
        Reason::DriveFault {
            axis: Some(a(4)),
            code: 0x2310,
        },
        Reason::DriveFault {
            axis: None,
            code: 0x10,
        },
        Reason::OutOfRange {
            axis: Some(a(1)),
            value: 200.5,
            min: -170.0,
            max: 170.0,
        },
        Reason::OutOfRange {
            axis: None,
            value: 2.0,
            min: 0.0,
            max: 1.0,
        },
        Reason::NotAvailable,
        Reason::NotSimulated,
        Reason::QueueFull {
            offered: 12,
            free: 3,
        },
        Reason::PositionLimit {
            axis: a(2),
            position_deg: 120.25,
            limit_deg: 120.0,
        },
        Reason::VelocityLimit {
            axis: a(1),
            velocity_deg_s: 99.0,
            limit_deg_s: 90.0,
        },
        Reason::BrakingDistance {
            axis: a(5),
            stop_deg: 121.0,
            limit_deg: 120.0,
        },
        Reason::FollowingError {
            axis: a(2),
            error_deg: 2.0561,
            band_deg: 2.0,
        },
        Reason::Overload {
            axis: a(2),
            current_a: 3.9962,
            limit_a: 4.0,
        },
        Reason::CalibrationFailed {
            axis: a(3),
            cause: CalibrationFailure::NoStop {
                searched_deg: 310.0,
            },
        },
        Reason::CalibrationFailed {
            axis: a(1),
            cause: CalibrationFailure::NoEdge {
                searched_deg: 350.0,
            },
        },
        Reason::CalibrationFailed {
            axis: a(6),
            cause: CalibrationFailure::DriveLost,
        },
        Reason::CalibrationFailed {
            axis: a(2),
            cause: CalibrationFailure::Inconsistent {
                first_deg: -125.02,
                second_deg: -123.51,
                tolerance_deg: 0.5,
            },
        },
        Reason::CalibrationFailed {
            axis: a(3),
            cause: CalibrationFailure::Implausible {
                found_deg: 99.742,
                configured_deg: 140.0,
                tolerance_deg: 0.5,
            },
        },
        Reason::CalibrationFailed {
            axis: a(4),
            cause: CalibrationFailure::Blocked {
                lag_deg: 3.167,
                bound_deg: 3.05,
            },
        },
        Reason::Aborted,
        Reason::Busy { remaining_s: 0.845 },
        Reason::PvtPoint {
            axis: a(1),
            point: 2,
            quantity: PvtQuantity::Velocity,
            value: 96.512,
            limit: 90.0,
        },
        Reason::PvtPoint {
            axis: a(3),
            point: 1,
            quantity: PvtQuantity::Position,
            value: 171.5,
            limit: 170.0,
        },
        Reason::PvtPoint {
            axis: a(6),
            point: 1000,
            quantity: PvtQuantity::Acceleration,
            value: -2500.25,
            limit: 2000.0,
        },
        Reason::Unreachable {
            axis: a(4),
            target_deg: 300.0,
            min_deg: -269.0,
            max_deg: 269.0,
        },
        Reason::NotOwner {
            owner: 0x1a2b_0000_0003,
        },
        Reason::LineUnreachable {
            axis: None,
            fault: LineFault::NoSolution { fraction: 0.3125 },
        },
        Reason::LineUnreachable {
            axis: None,
            fault: LineFault::Singular {
                fraction: 0.5,
                singularity: Singularity::Wrist,
                value: 1.25,
                margin: 2.0,
            },
        },
        Reason::LineUnreachable {
            axis: None,
            fault: LineFault::Singular {
                fraction: 0.1,
                singularity: Singularity::Shoulder,
                value: 0.0123,
                margin: 0.05,
            },
        },
        Reason::LineUnreachable {
            axis: Some(a(4)),
            fault: LineFault::JointJump {
                fraction: 0.75,
                step_deg: 40.5,
                allowed_deg: 3.25,
            },
        },
        Reason::LineOutOfRange {
            axis: a(5),
            fault: LineFault::OutOfRange {
                fraction: 0.26171875,
                value_deg: 119.08659727,
                limit_deg: 119.0,
            },
        },
        Reason::ShuttingDown,
    ]
    .into_iter()
    .chain(argument_refusals())
    .collect::<Vec<_>>()
    .iter()
    .map(|r| {
        let w = r.to_wire();
        let text = r.to_string().replace('\\', "\\\\").replace('"', "\\\"");
        format!(
            "[{}, {}, [{:?}, {:?}, {:?}, {:?}], \"{text}\"]",
            w.code.to_wire(),
            w.axis,
            w.values[0],
            w.values[1],
            w.values[2],
            w.values[3]
        )
    })
    .collect()
}

/// One refusal of every numeric argument of the protocol (`ranges::ARGS`), per-axis arrays
/// with an axis, with awkward numbers (1e-320, 169.00000000000003).
fn argument_refusals() -> Vec<mcm_shared::reply::Reason> {
    use mcm_shared::command::Axis;
    use mcm_shared::ranges::{ARGS, ArgRefusal};
    ARGS.iter()
        .enumerate()
        .map(|(k, spec)| {
            let axis = (spec.arg.per_axis_array() || k % 3 == 0)
                .then(|| Axis::new((k % 6) as u8 + 1).expect("axis 1..6"));
            mcm_shared::reply::Reason::InvalidArgument {
                refusal: ArgRefusal {
                    arg: spec.arg,
                    axis,
                    value: if k % 2 == 0 { 1e-320 } else { 200.5 },
                    min: -169.00000000000003,
                    max: 0.125 * k as f64 + 1.0,
                },
            }
        })
        .collect()
}

/// Commands of every kind the protocol sends to the core, with and without their optional
/// arguments, as a client writes them in JSON (`Command::to_json`, every argument given) and the
/// samples Rust encodes them into (`Command::requests`, `Request::encode`): `{"json": {...},
/// "samples": [[kind, flags, [args]], ...]}`, so that a client's port of the encoding (the
/// Python package's `wire.py`) can be checked.
fn encoded_commands() -> Vec<String> {
    use mcm_shared::config::RobotConfig;
    use mcm_shared::protocol::Command;
    let cfg = RobotConfig::prob2_default();
    let point = |k: f64| {
        format!(
            r#"{{"position":[{k},{k},{k},{k},{k},{k}],"velocity":[-{k},-{k},-{k},-{k},-{k},-{k}]}}"#
        )
    };
    let nine: Vec<String> = (1..=9).map(|k| point(f64::from(k))).collect();
    let pvt_points = format!(
        r#"{{"command":"pvt_points","arguments":{{"points":[{}]}}}}"#,
        nine.join(",")
    );
    [
        r#"{"command":"status"}"#,
        r#"{"command":"info"}"#,
        r#"{"command":"hold"}"#,
        r#"{"command":"calibrate"}"#,
        r#"{"command":"calibrate","arguments":{"which":"WRIST","elbow_direction":-1,"force_mechanical_stop":true}}"#,
        r#"{"command":"calibrate","arguments":{"which":3,"wrist_direction":-1}}"#,
        r#"{"command":"calibrate","arguments":{"which":"ELBOW"}}"#,
        r#"{"command":"release"}"#,
        r#"{"command":"torque_control"}"#,
        r#"{"command":"torque_control","arguments":{"timeout":-1,"gravity_compensation":false}}"#,
        r#"{"command":"set_torques","arguments":{"torques":[1,-2,0.5,0,0,-0.25]}}"#,
        r#"{"command":"velocity_control","arguments":{"timeout":0.5}}"#,
        r#"{"command":"velocity_control","arguments":{"timeout":-1}}"#,
        r#"{"command":"set_velocities","arguments":{"velocities":[10,0,0,0,0,-5.5]}}"#,
        r#"{"command":"set_cartesian_velocity","arguments":{"linear":[0.05,0,-0.01],"angular":[0,10,0]}}"#,
        r#"{"command":"set_cartesian_velocity","arguments":{"linear":[0,0,0.02],"angular":[-5,0,0],"frame":"tool"}}"#,
        r#"{"command":"set_tool","arguments":{"tcp":{"position":[0,0.01,0.15],"orientation":[0.5,-0.5,0.5,0.5]},"mass":2,"center_of_mass":[0,0,0.06]}}"#,
        r#"{"command":"set_tool","arguments":{"tcp":{"position":[0,0,0],"orientation":[0,0,0,1]},"mass":0.5,"center_of_mass":[0.01,0,0],"inertia":[0.01,0.02,0.025,0.001,0,-0.002]}}"#,
        r#"{"command":"identify_payload","arguments":{"apply":true}}"#,
        r#"{"command":"identify_payload"}"#,
        r#"{"command":"move_linear","arguments":{"position":[0.4,-0.1,0.5]}}"#,
        r#"{"command":"move_linear","arguments":{"position":[0.35,0.2,0.45],"orientation":[0,1,0,0],"velocity":0.1,"acceleration":2.5}}"#,
        r#"{"command":"move_linear","arguments":{"position":[0.3,0,0.6],"acceleration":0.5}}"#,
        r#"{"command":"pvt"}"#,
        r#"{"command":"pvt","arguments":{"dt":0.02}}"#,
        r#"{"command":"move_axis","arguments":{"axis_index":2,"target_position":30}}"#,
        r#"{"command":"move_axis","arguments":{"axis_index":6,"target_position":-12.5,"velocity_factor":0.5}}"#,
        r#"{"command":"move_all","arguments":{"target_positions":[1,2,3,4,5,6]}}"#,
        r#"{"command":"move_all","arguments":{"target_positions":[0,-20,30,0,45,0],"velocity_factor":0.25}}"#,
        pvt_points.as_str(),
        r#"{"command":"sim","arguments":{"emergency_stop":true,"block_axis":2,"external_torques":[0,5,0,0,0,0],"power_cycle":true}}"#,
        r#"{"command":"sim","arguments":{"emergency_stop":false,"disconnect_axis":1,"reconnect_axis":3,"unblock_axis":6}}"#,
        r#"{"command":"take_control"}"#,
        r#"{"command":"release_control"}"#,
    ]
    .iter()
    .map(|text| {
        let cmd = Command::from_json(text, &cfg).unwrap_or_else(|e| panic!("{text}: {e}"));
        let samples: Vec<String> = cmd
            .requests()
            .iter()
            .map(|r| {
                let s = r.encode();
                let args: Vec<String> = s.args.iter().map(|a| format!("{a:?}")).collect();
                format!("[{}, {}, [{}]]", s.kind, s.flags, args.join(", "))
            })
            .collect();
        format!(
            "{{\"json\": {}, \"samples\": [{}]}}",
            cmd.to_json(),
            samples.join(", ")
        )
    })
    .collect()
}

#[allow(dead_code)] // unused where `tests/end_to_end/python_layout.rs` includes this file as a module
fn main() {
    println!("{}", layout_json());
}
