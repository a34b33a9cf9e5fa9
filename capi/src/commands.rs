//! GENERATED from the list `capi/tests/wrappers/list.rs`; do not edit by hand:
//! `MCM_UPDATE_CAPI=1 cargo test -p mcm-capi --test wrappers` writes it anew.
//!
//! The C functions of the commands, `mcm_tcp_<name>` and `mcm_shm_<name>`: each checks its
//! arguments, calls the client (`TcpClient`, `ShmClient`) and writes its answer, under
//! `call` (a NULL handle refused, no panic across the ABI, a failure recorded in the
//! handle). Not real-time code, except where a function says so.

use crate::convert::{self, put, six, text};
use crate::error::{call, mcm_error_t};
use crate::shm::mcm_shm_client_t;
use crate::tcp::mcm_tcp_client_t;
use crate::types::*;
use mcm_client::mcm_shared::command::{MoveAll, MoveAxis};
use std::ffi::c_char;

/// Open a new connection in place of a broken one (repeats `authenticate`). Control of the arm
/// does not survive it: call `mcm_tcp_take_control` again.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_reconnect(client: *mut mcm_tcp_client_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_reconnect";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.reconnect()?;
            Ok(())
        })
    }
}

/// The newest state (`status`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_status(client: *mut mcm_tcp_client_t, out: *mut mcm_status_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_status";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = convert::out(out, F, "out")?;
            let a = h.client.status()?;
            *o = (&a).into();
            Ok(())
        })
    }
}

/// The newest state with its detail (`status` with `detail`): `has_detail` and the fields after
/// it are set.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_status_detail(client: *mut mcm_tcp_client_t, out: *mut mcm_status_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_status_detail";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = convert::out(out, F, "out")?;
            let a = h.client.status_detail()?;
            *o = (&a).into();
            Ok(())
        })
    }
}

/// The MCM's description: over TCP robot, version, cycle time and the limits of every axis
/// (`info`); over shared memory the core's number of axes and cycle period.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_info(client: *mut mcm_tcp_client_t, out: *mut mcm_info_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_info";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = convert::out(out, F, "out")?;
            let a = h.client.info()?;
            *o = (&a).into();
            Ok(())
        })
    }
}

/// Enter HOLD (open to every client; powers the drives from OFF or ERROR, stops a motion).
/// `status` (may be NULL): the state after it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_hold(client: *mut mcm_tcp_client_t, status: *mut mcm_status_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_hold";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.hold()?;
            put(status, (&a).into());
            Ok(())
        })
    }
}

/// Enter RELEASE (the arm can be moved by hand). `status` (may be NULL): the state after it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_release(client: *mut mcm_tcp_client_t, status: *mut mcm_status_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_release";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.release()?;
            put(status, (&a).into());
            Ok(())
        })
    }
}

/// Enter PVT with points spaced `dt_s` seconds. `status` (may be NULL): the state after it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_pvt(client: *mut mcm_tcp_client_t, dt_s: f64, status: *mut mcm_status_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_pvt";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.pvt(dt_s)?;
            put(status, (&a).into());
            Ok(())
        })
    }
}

/// Home the axes (`options` NULL: all axes, default directions); returns when the calibration
/// has finished (about 12 s on the simulated P-Rob2).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_calibrate(client: *mut mcm_tcp_client_t, options: *const mcm_calibrate_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_calibrate";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.calibrate(convert::calibrate_args(options, F)?.into())?;
            Ok(())
        })
    }
}

/// `hold`, then `calibrate` only when an axis is not calibrated yet; `*calibrated` (may be
/// NULL) says whether it calibrated. The arm ends in HOLD either way.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_calibrate_if_needed(client: *mut mcm_tcp_client_t, calibrated: *mut bool) -> mcm_error_t {
    const F: &str = "mcm_tcp_calibrate_if_needed";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.calibrate_if_needed()?;
            put(calibrated, a);
            Ok(())
        })
    }
}

/// Enter TORQUE_CONTROL (`options` NULL: `mcm_control_options_default()`). With `dt_status_s`
/// the status events come with `mcm_tcp_next_event`. `status` (may be NULL): the state after
/// it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_torque_control(client: *mut mcm_tcp_client_t, options: *const mcm_control_options_t, status: *mut mcm_status_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_torque_control";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.torque_control(convert::control_options(options).into())?;
            put(status, (&a).into());
            Ok(())
        })
    }
}

/// Set the six joint torques [Nm] in TORQUE_CONTROL without waiting for the answer (a refusal
/// comes later as an `MCM_EVENT_COMMAND_ERROR` event).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_set_torques(client: *mut mcm_tcp_client_t, torques: *const f64) -> mcm_error_t {
    const F: &str = "mcm_tcp_set_torques";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.set_torques(six(torques, F, "torques")?)?;
            Ok(())
        })
    }
}

/// Enter VELOCITY_CONTROL (`options` NULL: the defaults). `gravity_compensation` is not used.
/// With `dt_status_s` the status events come with `mcm_tcp_next_event`. `status` (may be NULL):
/// the state after it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_velocity_control(client: *mut mcm_tcp_client_t, options: *const mcm_control_options_t, status: *mut mcm_status_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_velocity_control";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.velocity_control(convert::control_options(options).into())?;
            put(status, (&a).into());
            Ok(())
        })
    }
}

/// Set the six joint velocities [deg/s] in VELOCITY_CONTROL without waiting for the answer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_set_velocities(client: *mut mcm_tcp_client_t, velocities: *const f64) -> mcm_error_t {
    const F: &str = "mcm_tcp_set_velocities";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.set_velocities(six(velocities, F, "velocities")?)?;
            Ok(())
        })
    }
}

/// Set the TCP's velocity in VELOCITY_CONTROL without waiting for the answer: `linear` three
/// values [m/s], `angular` three values [deg/s], in the axes of the base frame (`frame` 0) or
/// of the TCP's own (`frame` 1).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_set_cartesian_velocity(client: *mut mcm_tcp_client_t, linear: *const f64, angular: *const f64, frame: u32) -> mcm_error_t {
    const F: &str = "mcm_tcp_set_cartesian_velocity";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.set_cartesian_velocity(convert::three(linear, F, "linear")?, convert::three(angular, F, "angular")?, convert::frame(frame, F)?)?;
            Ok(())
        })
    }
}

/// Move axis `axis` (1 to 6) to `target_deg` at `velocity_factor` (0.001 to 1) of its limits;
/// returns as the motion starts (PVT mode).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_move_axis(client: *mut mcm_tcp_client_t, axis: u32, target_deg: f64, velocity_factor: f64) -> mcm_error_t {
    const F: &str = "mcm_tcp_move_axis";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.move_axis(convert::protocol_axis(axis, F)?, target_deg, velocity_factor)?;
            Ok(())
        })
    }
}

/// Move all axes together to the six `targets_deg`; `result` (may be NULL): the plan.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_move_all(client: *mut mcm_tcp_client_t, targets_deg: *const f64, velocity_factor: f64, result: *mut mcm_move_all_result_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_move_all";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.move_all(six(targets_deg, F, "targets_deg")?, velocity_factor)?;
            put(result, (&a).into());
            Ok(())
        })
    }
}

/// Move the TCP on a straight line (`line`: base frame; PVT mode); `result` (may be NULL): the
/// line as planned. Answered once the MCM has checked the whole path; a path the arm cannot
/// follow is refused (`unreachable`, `out_of_range`) and nothing moves.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_move_linear(client: *mut mcm_tcp_client_t, line: *const mcm_move_linear_t, result: *mut mcm_move_linear_result_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_move_linear";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.move_linear(convert::move_linear(line, F)?)?;
            put(result, (&a).into());
            Ok(())
        })
    }
}

/// Queue `count` PVT points, spaced by `pvt`'s `dt`. Any count from 1: up to 1000 points that
/// fit one line go as one command, queued whole or not at all; longer lists go as several
/// commands in order, and the first refused one ends the call (the commands before it stay
/// queued).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_pvt_points(client: *mut mcm_tcp_client_t, points: *const mcm_pvt_point_t, count: usize) -> mcm_error_t {
    const F: &str = "mcm_tcp_pvt_points";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.pvt_points(&convert::points(points, count, F)?)?;
            Ok(())
        })
    }
}

/// Set the tool the arm carries (its TCP and load), from the next cycle; in HOLD, or PVT at
/// standstill. A tool outside its checks is refused here (`MCM_ERR_ARGUMENT`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_set_tool(client: *mut mcm_tcp_client_t, tool: *const mcm_tool_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_set_tool";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.set_tool(convert::tool(tool, F)?)?;
            Ok(())
        })
    }
}

/// Every joint configuration [deg] that puts the TCP at `pose` (base frame), each within the
/// axis limits, the nearest to `seed_deg` first (six values; NULL: the present position).
/// Nothing moves; anyone may ask, in any mode. A pose no solution reaches is refused
/// (`MCM_ERR_REFUSED`, `mcm_tcp_last_reject`: `MCM_CODE_UNREACHABLE`). Executed by the gateway,
/// so TCP only: over shared memory there is no gateway and no configuration of the arm.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_inverse_kinematics(client: *mut mcm_tcp_client_t, pose: *const mcm_pose_t, seed_deg: *const f64, out: *mut mcm_ik_solutions_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_inverse_kinematics";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = convert::out(out, F, "out")?;
            let a = h.client.inverse_kinematics(convert::pose(pose, F)?, convert::optional_six(seed_deg, F, "seed_deg")?)?;
            *o = convert::ik_solutions(&a, F)?;
            Ok(())
        })
    }
}

/// Move the TCP to `pose` (base frame): a joint move, as `mcm_tcp_move_all`, to the inverse
/// kinematics' solution nearest the present position (PVT mode, control); `result` (may be
/// NULL): the plan. Executed by the gateway, so TCP only, as `mcm_tcp_inverse_kinematics`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_move_to_pose(client: *mut mcm_tcp_client_t, pose: *const mcm_pose_t, velocity_factor: f64, result: *mut mcm_move_all_result_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_move_to_pose";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.move_to_pose(convert::pose(pose, F)?, velocity_factor)?;
            put(result, (&a).into());
            Ok(())
        })
    }
}

/// Estimate the load on the flange (in HOLD at rest, calibrated): the arm moves through a few
/// poses and back, under 30 s; with `apply` the estimate becomes the tool's mass and centre of
/// mass. `result` (may be NULL): the estimate.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_identify_payload(client: *mut mcm_tcp_client_t, apply: bool, result: *mut mcm_payload_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_identify_payload";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.identify_payload(apply)?;
            put(result, (&a).into());
            Ok(())
        })
    }
}

/// Take control of the arm's motion (refused while another client controls it).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_take_control(client: *mut mcm_tcp_client_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_take_control";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.take_control()?;
            Ok(())
        })
    }
}

/// Give up control; what this client drove ends in HOLD.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_release_control(client: *mut mcm_tcp_client_t) -> mcm_error_t {
    const F: &str = "mcm_tcp_release_control";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.release_control()?;
            Ok(())
        })
    }
}

/// Present the shared secret (kept for `mcm_tcp_reconnect`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_authenticate(client: *mut mcm_tcp_client_t, secret: *const c_char) -> mcm_error_t {
    const F: &str = "mcm_tcp_authenticate";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.authenticate(text(secret, F, "secret")?)?;
            Ok(())
        })
    }
}

/// This client's id, `(pid << 32) | n` (`mcm_state_t.owner_client_id` when it controls the
/// arm). Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_client_id(client: *mut mcm_shm_client_t, out: *mut u64) -> mcm_error_t {
    const F: &str = "mcm_shm_client_id";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = convert::out(out, F, "out")?;
            let a = h.client.client_id();
            *o = a;
            Ok(())
        })
    }
}

/// Cycles whose state `mcm_shm_wait_state` never returned since connect. Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_missed_states(client: *mut mcm_shm_client_t, out: *mut u64) -> mcm_error_t {
    const F: &str = "mcm_shm_missed_states";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = convert::out(out, F, "out")?;
            let a = h.client.missed_states();
            *o = a;
            Ok(())
        })
    }
}

/// The next cycle's state: blocks on the core's event (no spinning) at most 0.5 s
/// (`MCM_ERR_TIMEOUT`). Each state is returned once. Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_wait_state(client: *mut mcm_shm_client_t, out: *mut mcm_state_t) -> mcm_error_t {
    const F: &str = "mcm_shm_wait_state";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = convert::out(out, F, "out")?;
            let a = h.client.wait_state()?;
            *o = (&a).into();
            Ok(())
        })
    }
}

/// `mcm_shm_wait_state` with its own bound [s]. Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_wait_state_timeout(client: *mut mcm_shm_client_t, timeout_s: f64, out: *mut mcm_state_t) -> mcm_error_t {
    const F: &str = "mcm_shm_wait_state_timeout";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = convert::out(out, F, "out")?;
            let a = h.client.wait_state_timeout(convert::seconds(timeout_s, F, "timeout_s")?)?;
            *o = (&a).into();
            Ok(())
        })
    }
}

/// The newest state without waiting (it may be the one returned last). Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_latest(client: *mut mcm_shm_client_t, out: *mut mcm_state_t) -> mcm_error_t {
    const F: &str = "mcm_shm_latest";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = convert::out(out, F, "out")?;
            let a = h.client.latest();
            *o = (&a).into();
            Ok(())
        })
    }
}

/// The MCM's description: over TCP robot, version, cycle time and the limits of every axis
/// (`info`); over shared memory the core's number of axes and cycle period.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_info(client: *mut mcm_shm_client_t, out: *mut mcm_shm_info_t) -> mcm_error_t {
    const F: &str = "mcm_shm_info";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = convert::out(out, F, "out")?;
            let a = h.client.info()?;
            *o = (&a).into();
            Ok(())
        })
    }
}

/// Enter HOLD (open to every client; powers the drives from OFF or ERROR, stops a motion).
/// Waits for the core's reply.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_hold(client: *mut mcm_shm_client_t) -> mcm_error_t {
    const F: &str = "mcm_shm_hold";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.hold()?;
            Ok(())
        })
    }
}

/// Enter RELEASE (the arm can be moved by hand).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_release(client: *mut mcm_shm_client_t) -> mcm_error_t {
    const F: &str = "mcm_shm_release";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.release()?;
            Ok(())
        })
    }
}

/// Enter PVT with points spaced `dt_s` seconds.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_pvt(client: *mut mcm_shm_client_t, dt_s: f64) -> mcm_error_t {
    const F: &str = "mcm_shm_pvt";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.pvt(dt_s)?;
            Ok(())
        })
    }
}

/// Home the axes (`options` NULL: all axes, default directions); returns when the calibration
/// has finished (about 12 s on the simulated P-Rob2).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_calibrate(client: *mut mcm_shm_client_t, options: *const mcm_calibrate_t) -> mcm_error_t {
    const F: &str = "mcm_shm_calibrate";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.calibrate(convert::calibrate_args(options, F)?.into())?;
            Ok(())
        })
    }
}

/// `hold`, then `calibrate` only when an axis is not calibrated yet; `*calibrated` (may be
/// NULL) says whether it calibrated. The arm ends in HOLD either way.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_calibrate_if_needed(client: *mut mcm_shm_client_t, calibrated: *mut bool) -> mcm_error_t {
    const F: &str = "mcm_shm_calibrate_if_needed";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.calibrate_if_needed()?;
            put(calibrated, a);
            Ok(())
        })
    }
}

/// Enter TORQUE_CONTROL (`options` NULL: `mcm_control_options_default()`). `dt_status_s` is not
/// used here.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_torque_control(client: *mut mcm_shm_client_t, options: *const mcm_control_options_t) -> mcm_error_t {
    const F: &str = "mcm_shm_torque_control";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.torque_control(convert::control_options(options).into())?;
            Ok(())
        })
    }
}

/// Set the six joint torques [Nm] in TORQUE_CONTROL without waiting for the answer (a refusal
/// comes later as an `MCM_EVENT_COMMAND_ERROR` event). Real-time safe (one small allocation
/// inside iceoryx2's publisher).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_set_torques(client: *mut mcm_shm_client_t, torques: *const f64) -> mcm_error_t {
    const F: &str = "mcm_shm_set_torques";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.set_torques(six(torques, F, "torques")?)?;
            Ok(())
        })
    }
}

/// Enter VELOCITY_CONTROL (`options` NULL: the defaults). Only `timeout_s` is used.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_velocity_control(client: *mut mcm_shm_client_t, options: *const mcm_control_options_t) -> mcm_error_t {
    const F: &str = "mcm_shm_velocity_control";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.velocity_control(convert::control_options(options).into())?;
            Ok(())
        })
    }
}

/// Set the six joint velocities [deg/s] in VELOCITY_CONTROL without waiting for the answer.
/// Real-time safe (one small allocation inside iceoryx2's publisher).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_set_velocities(client: *mut mcm_shm_client_t, velocities: *const f64) -> mcm_error_t {
    const F: &str = "mcm_shm_set_velocities";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.set_velocities(six(velocities, F, "velocities")?)?;
            Ok(())
        })
    }
}

/// Set the TCP's velocity in VELOCITY_CONTROL without waiting for the answer: `linear` three
/// values [m/s], `angular` three values [deg/s], in the axes of the base frame (`frame` 0) or
/// of the TCP's own (`frame` 1). Real-time safe (one small allocation inside iceoryx2's
/// publisher).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_set_cartesian_velocity(client: *mut mcm_shm_client_t, linear: *const f64, angular: *const f64, frame: u32) -> mcm_error_t {
    const F: &str = "mcm_shm_set_cartesian_velocity";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.set_cartesian_velocity(convert::three(linear, F, "linear")?, convert::three(angular, F, "angular")?, convert::frame(frame, F)?)?;
            Ok(())
        })
    }
}

/// Move axis `axis` (1 to 6) to `target_deg` at `velocity_factor` (0.001 to 1) of its limits;
/// returns as the motion starts (PVT mode).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_move_axis(client: *mut mcm_shm_client_t, axis: u32, target_deg: f64, velocity_factor: f64) -> mcm_error_t {
    const F: &str = "mcm_shm_move_axis";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.move_axis(MoveAxis { axis: convert::axis(axis, F)?, target_deg, velocity_factor })?;
            Ok(())
        })
    }
}

/// Move all axes together to the six `targets_deg`; `result` (may be NULL): the plan.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_move_all(client: *mut mcm_shm_client_t, targets_deg: *const f64, velocity_factor: f64, result: *mut mcm_move_all_result_t) -> mcm_error_t {
    const F: &str = "mcm_shm_move_all";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.move_all(MoveAll { targets_deg: six(targets_deg, F, "targets_deg")?, velocity_factor })?;
            put(result, (&a).into());
            Ok(())
        })
    }
}

/// Move the TCP on a straight line (`line`: base frame; PVT mode); `result` (may be NULL): the
/// line as planned. Answered once the MCM has checked the whole path; a path the arm cannot
/// follow is refused (`unreachable`, `out_of_range`) and nothing moves.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_move_linear(client: *mut mcm_shm_client_t, line: *const mcm_move_linear_t, result: *mut mcm_move_linear_result_t) -> mcm_error_t {
    const F: &str = "mcm_shm_move_linear";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.move_linear(convert::move_linear(line, F)?)?;
            put(result, (&a).into());
            Ok(())
        })
    }
}

/// Queue `count` PVT points, spaced by `pvt`'s `dt`. 1 to 1000 points, queued whole or not at
/// all.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_pvt_points(client: *mut mcm_shm_client_t, points: *const mcm_pvt_point_t, count: usize) -> mcm_error_t {
    const F: &str = "mcm_shm_pvt_points";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.pvt_points(&convert::points(points, count, F)?)?;
            Ok(())
        })
    }
}

/// Set the tool the arm carries (its TCP and load), from the next cycle; in HOLD, or PVT at
/// standstill. A tool outside its checks is refused here (`MCM_ERR_ARGUMENT`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_set_tool(client: *mut mcm_shm_client_t, tool: *const mcm_tool_t) -> mcm_error_t {
    const F: &str = "mcm_shm_set_tool";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.set_tool(convert::tool(tool, F)?)?;
            Ok(())
        })
    }
}

/// Estimate the load on the flange (in HOLD at rest, calibrated): the arm moves through a few
/// poses and back, under 30 s; with `apply` the estimate becomes the tool's mass and centre of
/// mass. `result` (may be NULL): the estimate.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_identify_payload(client: *mut mcm_shm_client_t, apply: bool, result: *mut mcm_payload_t) -> mcm_error_t {
    const F: &str = "mcm_shm_identify_payload";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let a = h.client.identify_payload(apply)?;
            put(result, (&a).into());
            Ok(())
        })
    }
}

/// Take control of the arm's motion (refused while another client controls it).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_take_control(client: *mut mcm_shm_client_t) -> mcm_error_t {
    const F: &str = "mcm_shm_take_control";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.take_control()?;
            Ok(())
        })
    }
}

/// Give up control; what this client drove ends in HOLD.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_release_control(client: *mut mcm_shm_client_t) -> mcm_error_t {
    const F: &str = "mcm_shm_release_control";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            h.client.release_control()?;
            Ok(())
        })
    }
}
