//! `mcm_tcp_*`: the JSON protocol over TCP (mcm-client's `tcp::TcpClient`), blocking, every
//! call bounded by a timeout. Not real-time code: calls allocate and wait on the network.

use crate::args::{self, put, six, text};
use crate::error::{Fail, Handle, LastError, c_string, call, close, guard, mcm_error_t};
use crate::types::*;
use mcm_client::mcm_shared::command::{PvtPoint, Which};
use mcm_client::tcp::{CalibrateOptions, Event, TcpClient, TorqueOptions, VelocityOptions};
use std::ffi::{CString, c_char, c_void};

/// A connection to the MCM's JSON port (opaque; `mcm_tcp_connect`, `mcm_tcp_close`).
pub struct mcm_tcp_client_t {
    client: TcpClient,
    last: LastError,
    /// The message of the last event handed out.
    event_message: CString,
}

impl Handle for mcm_tcp_client_t {
    fn last_error(&mut self) -> &mut LastError {
        &mut self.last
    }
}

/// Connect to the MCM's JSON port at `addr` ("host:port", e.g. "127.0.0.1:18010"); on success
/// `*out` is the new handle (close it with `mcm_tcp_close`), else NULL and `mcm_last_error()`
/// says why.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_connect(
    addr: *const c_char,
    out: *mut *mut mcm_tcp_client_t,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_connect";
    guard(
        F,
        |_| {},
        || {
            // SAFETY: the header's contract for both pointers.
            let slot = unsafe { args::out(out, F, "out") }?;
            *slot = std::ptr::null_mut();
            // SAFETY: as above.
            let addr = unsafe { text(addr, F, "addr") }?;
            let client = TcpClient::connect(addr)?;
            *slot = Box::into_raw(Box::new(mcm_tcp_client_t {
                client,
                last: LastError::default(),
                event_message: CString::default(),
            }));
            Ok(())
        },
    )
}

/// Close the connection and free the handle (NULL: nothing happens). What this connection
/// controlled ends in HOLD (the gateway releases its control).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_close(client: *mut mcm_tcp_client_t) {
    // SAFETY: NULL or a handle from mcm_tcp_connect, closed once (the header's contract).
    unsafe { close(client) }
}

/// The message of the last failed call on this handle ("" when none failed); valid until
/// the next failing call on it. Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_last_error(client: *const mcm_tcp_client_t) -> *const c_char {
    // SAFETY: NULL or a live handle (the header's contract).
    match unsafe { client.as_ref() } {
        Some(h) => h.last.message.as_ptr(),
        None => c"mcm_tcp_last_error: argument `client` is NULL".as_ptr(),
    }
}

/// The MCM's reject code of the last failed call on this handle (0: none or not recognised
/// from the MCM's words). Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_last_reject(client: *const mcm_tcp_client_t) -> u32 {
    // SAFETY: NULL or a live handle.
    unsafe { client.as_ref() }.map_or(0, |h| h.last.reject)
}

/// Open a new connection in place of a broken one (repeats `authenticate`). Control of the arm
/// does not survive it: call `mcm_tcp_take_control` again.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_reconnect(client: *mut mcm_tcp_client_t) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe { call("mcm_tcp_reconnect", client, |h| Ok(h.client.reconnect()?)) }
}

/// The newest state (`status`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_status(
    client: *mut mcm_tcp_client_t,
    out: *mut mcm_status_t,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_status";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = args::out(out, F, "out")?;
            *o = (&h.client.status()?).into();
            Ok(())
        })
    }
}

/// The newest state with its detail (`status` with `detail`): `has_detail` and the fields
/// after it are set.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_status_detail(
    client: *mut mcm_tcp_client_t,
    out: *mut mcm_status_t,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_status_detail";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = args::out(out, F, "out")?;
            *o = (&h.client.status_detail()?).into();
            Ok(())
        })
    }
}

/// Robot, version, cycle time and the limits of every axis (`info`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_info(
    client: *mut mcm_tcp_client_t,
    out: *mut mcm_info_t,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_info";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = args::out(out, F, "out")?;
            *o = (&h.client.info()?).into();
            Ok(())
        })
    }
}

/// Enter HOLD (open to every client; powers the drives from OFF or ERROR, stops a motion).
/// `status` (may be NULL): the state in HOLD.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_hold(
    client: *mut mcm_tcp_client_t,
    status: *mut mcm_status_t,
) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_tcp_hold", client, |h| {
            put(status, (&h.client.hold()?).into());
            Ok(())
        })
    }
}

/// Enter RELEASE (the arm can be moved by hand). `status` may be NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_release(
    client: *mut mcm_tcp_client_t,
    status: *mut mcm_status_t,
) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_tcp_release", client, |h| {
            put(status, (&h.client.release()?).into());
            Ok(())
        })
    }
}

/// Enter PVT with points spaced `dt_s` seconds. `status` may be NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_pvt(
    client: *mut mcm_tcp_client_t,
    dt_s: f64,
    status: *mut mcm_status_t,
) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_tcp_pvt", client, |h| {
            put(status, (&h.client.pvt(dt_s)?).into());
            Ok(())
        })
    }
}

/// Home the axes (`options` NULL: all axes, default directions); returns when the calibration
/// has finished (about 12 s on the simulated P-Rob2).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_calibrate(
    client: *mut mcm_tcp_client_t,
    options: *const mcm_calibrate_t,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_calibrate";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let c = args::calibrate(options, F)?;
            h.client.calibrate(CalibrateOptions {
                which: Some(c.which).filter(|w| *w != Which::All),
                elbow_direction: c.elbow_direction,
                wrist_direction: c.wrist_direction,
                force_mechanical_stop: c.force_mechanical_stop,
            })?;
            Ok(())
        })
    }
}

/// `hold`, then `calibrate` only when an axis is not calibrated yet; `*calibrated` (may be
/// NULL) says whether it calibrated. The arm ends in HOLD either way.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_calibrate_if_needed(
    client: *mut mcm_tcp_client_t,
    calibrated: *mut bool,
) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_tcp_calibrate_if_needed", client, |h| {
            put(calibrated, h.client.calibrate_if_needed()?);
            Ok(())
        })
    }
}

/// Enter TORQUE_CONTROL (`options` NULL: `mcm_control_options_default()`); with
/// `dt_status_s` the status events come with `mcm_tcp_next_event`. `status` may be NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_torque_control(
    client: *mut mcm_tcp_client_t,
    options: *const mcm_control_options_t,
    status: *mut mcm_status_t,
) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_tcp_torque_control", client, |h| {
            let o = args::control_options(options);
            let s = h.client.torque_control(TorqueOptions {
                timeout_s: args::timeout(o.timeout_s),
                dt_status_s: (o.dt_status_s > 0.0).then_some(o.dt_status_s),
                gravity_compensation: o.gravity_compensation,
            })?;
            put(status, (&s).into());
            Ok(())
        })
    }
}

/// Set the six joint torques [Nm] in TORQUE_CONTROL; returns once written (a refusal comes
/// later as an `MCM_EVENT_COMMAND_ERROR` event).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_set_torques(
    client: *mut mcm_tcp_client_t,
    torques: *const f64,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_set_torques";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            Ok(h.client.set_torques(six(torques, F, "torques")?)?)
        })
    }
}

/// Enter VELOCITY_CONTROL (`options` NULL: the defaults; `gravity_compensation` is not used).
/// `status` may be NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_velocity_control(
    client: *mut mcm_tcp_client_t,
    options: *const mcm_control_options_t,
    status: *mut mcm_status_t,
) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_tcp_velocity_control", client, |h| {
            let o = args::control_options(options);
            let s = h.client.velocity_control(VelocityOptions {
                timeout_s: args::timeout(o.timeout_s),
                dt_status_s: (o.dt_status_s > 0.0).then_some(o.dt_status_s),
            })?;
            put(status, (&s).into());
            Ok(())
        })
    }
}

/// Set the six joint velocities [deg/s] in VELOCITY_CONTROL; returns once written.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_set_velocities(
    client: *mut mcm_tcp_client_t,
    velocities: *const f64,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_set_velocities";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            Ok(h.client.set_velocities(six(velocities, F, "velocities")?)?)
        })
    }
}

/// Move axis `axis` (1 to 6) to `target_deg` at `velocity_factor` (0.001 to 1) of its limits;
/// returns as the motion starts (PVT mode).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_move_axis(
    client: *mut mcm_tcp_client_t,
    axis: u32,
    target_deg: f64,
    velocity_factor: f64,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_move_axis";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            // The MCM words a wrong axis itself (MCM_ERR_INVALID); only what does not fit the
            // protocol's number is refused here.
            let a = u8::try_from(axis).map_err(|_| {
                Fail::new(
                    mcm_error_t::MCM_ERR_ARGUMENT,
                    format!("{F}: argument `axis` = {axis} is not allowed; expected an axis number from 1 to 6"),
                )
            })?;
            Ok(h.client.move_axis(a, target_deg, velocity_factor)?)
        })
    }
}

/// Move all axes together to the six `targets_deg`; `result` (may be NULL): the plan.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_move_all(
    client: *mut mcm_tcp_client_t,
    targets_deg: *const f64,
    velocity_factor: f64,
    result: *mut mcm_move_all_result_t,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_move_all";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let r = h
                .client
                .move_all(six(targets_deg, F, "targets_deg")?, velocity_factor)?;
            put(result, (&r).into());
            Ok(())
        })
    }
}

/// Queue `count` PVT points (spaced by `pvt`'s `dt`); long lists go as several commands, and
/// the first refused one ends the call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_pvt_points(
    client: *mut mcm_tcp_client_t,
    points: *const mcm_pvt_point_t,
    count: usize,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_pvt_points";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            if points.is_null() {
                return Err(Fail::null(F, "points"));
            }
            // SAFETY: `count` readable points (the header's contract).
            let pts = std::slice::from_raw_parts(points, count);
            let pts: Vec<PvtPoint> = pts.iter().map(PvtPoint::from).collect();
            Ok(h.client.pvt_points(&pts)?)
        })
    }
}

/// Take control of the arm's motion (refused while another client controls it).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_take_control(client: *mut mcm_tcp_client_t) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_tcp_take_control", client, |h| {
            Ok(h.client.take_control()?)
        })
    }
}

/// Give up control; what this connection drove ends in HOLD.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_release_control(client: *mut mcm_tcp_client_t) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_tcp_release_control", client, |h| {
            Ok(h.client.release_control()?)
        })
    }
}

/// Present the shared secret (kept for `mcm_tcp_reconnect`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_authenticate(
    client: *mut mcm_tcp_client_t,
    secret: *const c_char,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_authenticate";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            Ok(h.client.authenticate(text(secret, F, "secret")?)?)
        })
    }
}

/// The next spontaneous message (safety errors, status events of a session, refusals of
/// `set_torques`/`set_velocities`, notices): a queued one at once, else the first within
/// `timeout_s`. `*got` says whether `*out` was filled; its `message` lives until the next call
/// on this handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_next_event(
    client: *mut mcm_tcp_client_t,
    timeout_s: f64,
    out: *mut mcm_event_t,
    got: *mut bool,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_next_event";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = args::out(out, F, "out")?;
            let got = args::out(got, F, "got")?;
            *got = false;
            let Some(e) = h
                .client
                .next_event(args::seconds(timeout_s, F, "timeout_s")?)?
            else {
                return Ok(());
            };
            let mut ev = mcm_event_t {
                kind: MCM_EVENT_NOTICE,
                code: 0,
                axis: 0,
                message: std::ptr::null(),
                status: mcm_status_t::default(),
            };
            let message = match e {
                Event::Status(s) => {
                    ev.kind = MCM_EVENT_STATUS;
                    ev.status = (&*s).into();
                    String::new()
                }
                Event::SafetyError {
                    check,
                    axis,
                    message,
                    ..
                } => {
                    ev.kind = MCM_EVENT_SAFETY_ERROR;
                    ev.code = check.map_or(0, |c| c.to_wire());
                    ev.axis = axis.map_or(0, u32::from);
                    message
                }
                Event::CommandError(m) => {
                    ev.kind = MCM_EVENT_COMMAND_ERROR;
                    ev.code = m.code.map_or(0, |c| c.to_wire());
                    m.message
                }
                Event::Notice(n) => n,
            };
            h.event_message = c_string(&message);
            ev.message = h.event_message.as_ptr();
            *o = ev;
            *got = true;
            Ok(())
        })
    }
}

/// Ask for the state every 10 ms until `predicate(status, user)` is nonzero, at most
/// `timeout_s`; `MCM_ERR_NOT_REACHED` naming `what` after that. `status` (may be NULL): the
/// state that satisfied it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_wait_until(
    client: *mut mcm_tcp_client_t,
    what: *const c_char,
    timeout_s: f64,
    predicate: mcm_status_predicate_fn,
    user: *mut c_void,
    status: *mut mcm_status_t,
) -> mcm_error_t {
    const F: &str = "mcm_tcp_wait_until";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let what = text(what, F, "what")?;
            let pred = predicate.ok_or_else(|| Fail::null(F, "predicate"))?;
            let wait = args::seconds(timeout_s, F, "timeout_s")?;
            let s = h.client.wait_until(what, wait, |s| {
                let c: mcm_status_t = s.into();
                // SAFETY: a C function with a valid status and the caller's `user`.
                pred(&c, user) != 0
            })?;
            put(status, (&s).into());
            Ok(())
        })
    }
}
