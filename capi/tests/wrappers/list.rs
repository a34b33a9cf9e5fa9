//! The commands of the C API, one entry each: the C functions `mcm_tcp_<name>` and
//! `mcm_shm_<name>` (in `capi/src/commands.rs`) are generated from this list by `main.rs`.
//!
//! An entry names the command, the transports that have it, its documentation, its C
//! parameters (after the handle), what it answers and the call of the client
//! (`mcm_client::tcp::TcpClient`, `mcm_client::shm::ShmClient`) it makes, in Rust with the
//! checked arguments (`F` is the function's name, for the refusals). A call that differs
//! between the clients is given per transport.

use super::{Answer, Command, both, shm, tcp};

/// Every generated command, in the header's order.
pub fn commands() -> Vec<Command> {
    vec![
        tcp("reconnect", "Open a new connection in place of a broken one (repeats `authenticate`). Control of the arm does not survive it: call `mcm_tcp_take_control` again.").call("reconnect()"),
        tcp("status", "The newest state (`status`).").answer(Answer::Out("out", "mcm_status_t", "(&a).into()")).call("status()"),
        tcp("status_detail", "The newest state with its detail (`status` with `detail`): `has_detail` and the fields after it are set.").answer(Answer::Out("out", "mcm_status_t", "(&a).into()")).call("status_detail()"),
        shm("client_id", "This client's id, `(pid << 32) | n` (`mcm_state_t.owner_client_id` when it controls the arm). Real-time safe.").answer(Answer::Out("out", "u64", "a")).call("client_id()").infallible(),
        shm("missed_states", "Cycles whose state `mcm_shm_wait_state` never returned since connect. Real-time safe.").answer(Answer::Out("out", "u64", "a")).call("missed_states()").infallible(),
        shm("wait_state", "The next cycle's state: blocks on the core's event (no spinning) at most 0.5 s (`MCM_ERR_TIMEOUT`). Each state is returned once. Real-time safe.").answer(Answer::Out("out", "mcm_state_t", "(&a).into()")).call("wait_state()"),
        shm("wait_state_timeout", "`mcm_shm_wait_state` with its own bound [s]. Real-time safe.").param("timeout_s", "f64").answer(Answer::Out("out", "mcm_state_t", "(&a).into()")).call("wait_state_timeout(convert::seconds(timeout_s, F, \"timeout_s\")?)"),
        shm("latest", "The newest state without waiting (it may be the one returned last). Real-time safe.").answer(Answer::Out("out", "mcm_state_t", "(&a).into()")).call("latest()").infallible(),
        both("info", "The MCM's description: over TCP robot, version, cycle time and the limits of every axis (`info`); over shared memory the core's number of axes and cycle period.").answer(Answer::OutPer("out", "mcm_info_t", "mcm_shm_info_t", "(&a).into()")).call("info()"),
        both("hold", "Enter HOLD (open to every client; powers the drives from OFF or ERROR, stops a motion).").shm_doc("Waits for the core's reply.").answer(Answer::Mode).call("hold()"),
        both("release", "Enter RELEASE (the arm can be moved by hand).").answer(Answer::Mode).call("release()"),
        both("pvt", "Enter PVT with points spaced `dt_s` seconds.").param("dt_s", "f64").answer(Answer::Mode).call("pvt(dt_s)"),
        both("calibrate", "Home the axes (`options` NULL: all axes, default directions); returns when the calibration has finished (about 12 s on the simulated P-Rob2).").param("options", "*const mcm_calibrate_t").call("calibrate(convert::calibrate_args(options, F)?.into())"),
        both("calibrate_if_needed", "`hold`, then `calibrate` only when an axis is not calibrated yet; `*calibrated` (may be NULL) says whether it calibrated. The arm ends in HOLD either way.").answer(Answer::Put("calibrated", "bool", "a")).call("calibrate_if_needed()"),
        both("torque_control", "Enter TORQUE_CONTROL (`options` NULL: `mcm_control_options_default()`).").tcp_doc("With `dt_status_s` the status events come with `mcm_tcp_next_event`.").shm_doc("`dt_status_s` is not used here.").param("options", "*const mcm_control_options_t").answer(Answer::Mode).call("torque_control(convert::control_options(options).into())"),
        both("set_torques", "Set the six joint torques [Nm] in TORQUE_CONTROL without waiting for the answer (a refusal comes later as an `MCM_EVENT_COMMAND_ERROR` event).").shm_doc("Real-time safe (one small allocation inside iceoryx2's publisher).").param("torques", "*const f64").call("set_torques(six(torques, F, \"torques\")?)"),
        both("velocity_control", "Enter VELOCITY_CONTROL (`options` NULL: the defaults).").tcp_doc("`gravity_compensation` is not used. With `dt_status_s` the status events come with `mcm_tcp_next_event`.").shm_doc("Only `timeout_s` is used.").param("options", "*const mcm_control_options_t").answer(Answer::Mode).call("velocity_control(convert::control_options(options).into())"),
        both("set_velocities", "Set the six joint velocities [deg/s] in VELOCITY_CONTROL without waiting for the answer.").shm_doc("Real-time safe (one small allocation inside iceoryx2's publisher).").param("velocities", "*const f64").call("set_velocities(six(velocities, F, \"velocities\")?)"),
        both("move_axis", "Move axis `axis` (1 to 6) to `target_deg` at `velocity_factor` (0.001 to 1) of its limits; returns as the motion starts (PVT mode).").param("axis", "u32").param("target_deg", "f64").param("velocity_factor", "f64").call_per("move_axis(convert::protocol_axis(axis, F)?, target_deg, velocity_factor)", "move_axis(MoveAxis { axis: convert::axis(axis, F)?, target_deg, velocity_factor })"),
        both("move_all", "Move all axes together to the six `targets_deg`; `result` (may be NULL): the plan.").param("targets_deg", "*const f64").param("velocity_factor", "f64").answer(Answer::Put("result", "mcm_move_all_result_t", "(&a).into()")).call_per("move_all(six(targets_deg, F, \"targets_deg\")?, velocity_factor)", "move_all(MoveAll { targets_deg: six(targets_deg, F, \"targets_deg\")?, velocity_factor })"),
        both("move_linear", "Move the TCP on a straight line (`line`: base frame; PVT mode); `result` (may be NULL): the line as planned. Answered once the MCM has checked the whole path; a path the arm cannot follow is refused (`unreachable`, `out_of_range`) and nothing moves.").param("line", "*const mcm_move_linear_t").answer(Answer::Put("result", "mcm_move_linear_result_t", "(&a).into()")).call("move_linear(convert::move_linear(line, F)?)"),
        both("pvt_points", "Queue `count` PVT points, spaced by `pvt`'s `dt`.").tcp_doc("Any count from 1: up to 1000 points that fit one line go as one command, queued whole or not at all; longer lists go as several commands in order, and the first refused one ends the call (the commands before it stay queued).").shm_doc("1 to 1000 points, queued whole or not at all.").param("points", "*const mcm_pvt_point_t").param("count", "usize").call("pvt_points(&convert::points(points, count, F)?)"),
        both("set_tool", "Set the tool the arm carries (its TCP and load), from the next cycle; in HOLD, or PVT at standstill. A tool outside its checks is refused here (`MCM_ERR_ARGUMENT`).").param("tool", "*const mcm_tool_t").call("set_tool(convert::tool(tool, F)?)"),
        both("take_control", "Take control of the arm's motion (refused while another client controls it).").call("take_control()"),
        both("release_control", "Give up control; what this client drove ends in HOLD.").call("release_control()"),
        tcp("authenticate", "Present the shared secret (kept for `mcm_tcp_reconnect`).").param("secret", "*const c_char").call("authenticate(text(secret, F, \"secret\")?)"),
    ]
}
