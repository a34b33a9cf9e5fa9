//! `mcm_shm_*`: the real-time core's shared-memory services (mcm-client's `shm::ShmClient`),
//! with the control loop. `mcm_shm_wait_state`, `mcm_shm_latest`, `mcm_shm_set_torques`,
//! `mcm_shm_set_velocities`, the accessors and the running loop of `mcm_shm_control` are
//! real-time code (no lock, no blocking; a command sent makes one allocation inside iceoryx2's
//! publisher, see the crate's documentation); the commands that wait for a reply are not.

use crate::args::{self, put, six, text};
use crate::error::{
    Fail, Handle, LastError, c_string, call, close, control_end, guard, mcm_error_t,
};
use crate::types::*;
use mcm_client::Mode;
use mcm_client::mcm_shared::command::{
    MoveAll, MoveAxis, PvtPoint, TorqueControl, VelocityControl,
};
use mcm_client::mcm_shared::reply::Outcome;
use mcm_client::shm::{ControlOutput, ShmClient, ShmEvent};
use std::ffi::{CString, c_char, c_void};

/// A client of the MCM's shared-memory services (opaque; `mcm_shm_connect`,
/// `mcm_shm_close`). Bound to the thread that created it.
pub struct mcm_shm_client_t {
    client: ShmClient,
    last: LastError,
    event_message: CString,
}

impl Handle for mcm_shm_client_t {
    fn last_error(&mut self) -> &mut LastError {
        &mut self.last
    }
}

/// Open the services of the MCM instance `instance` ("default" unless the MCM was started with
/// `--instance`); on success `*out` is the new handle, else NULL and `mcm_last_error()` says
/// why (`MCM_ERR_NOT_RUNNING`, `MCM_ERR_INCOMPATIBLE`, ...).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_connect(
    instance: *const c_char,
    out: *mut *mut mcm_shm_client_t,
) -> mcm_error_t {
    const F: &str = "mcm_shm_connect";
    guard(
        F,
        |_| {},
        || {
            // SAFETY: the header's contract for both pointers.
            let slot = unsafe { args::out(out, F, "out") }?;
            *slot = std::ptr::null_mut();
            // SAFETY: as above.
            let instance = unsafe { text(instance, F, "instance") }?;
            let client = ShmClient::connect(instance)?;
            *slot = Box::into_raw(Box::new(mcm_shm_client_t {
                client,
                last: LastError::default(),
                event_message: CString::default(),
            }));
            Ok(())
        },
    )
}

/// Free the handle (NULL: nothing happens); it tells the core the client is gone, so what it
/// drove ends in HOLD.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_close(client: *mut mcm_shm_client_t) {
    // SAFETY: NULL or a handle from mcm_shm_connect, closed once (the header's contract).
    unsafe { close(client) }
}

/// The message of the last failed call on this handle ("" when none failed). Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_last_error(client: *const mcm_shm_client_t) -> *const c_char {
    // SAFETY: NULL or a live handle.
    match unsafe { client.as_ref() } {
        Some(h) => h.last.message.as_ptr(),
        None => c"mcm_shm_last_error: argument `client` is NULL".as_ptr(),
    }
}

/// The MCM's reject code of the last failed call on this handle (0: none). Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_last_reject(client: *const mcm_shm_client_t) -> u32 {
    // SAFETY: NULL or a live handle.
    unsafe { client.as_ref() }.map_or(0, |h| h.last.reject)
}

/// This client's id, `(pid << 32) | n` (`mcm_state_t.owner_client_id` when it controls the
/// arm). Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_client_id(
    client: *mut mcm_shm_client_t,
    out: *mut u64,
) -> mcm_error_t {
    const F: &str = "mcm_shm_client_id";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            *args::out(out, F, "out")? = h.client.client_id();
            Ok(())
        })
    }
}

/// Cycles whose state `mcm_shm_wait_state` never returned since connect. Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_missed_states(
    client: *mut mcm_shm_client_t,
    out: *mut u64,
) -> mcm_error_t {
    const F: &str = "mcm_shm_missed_states";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            *args::out(out, F, "out")? = h.client.missed_states();
            Ok(())
        })
    }
}

/// The next cycle's state: blocks on the core's event (no spinning) at most 0.5 s
/// (`MCM_ERR_TIMEOUT`). Each state is returned once. Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_wait_state(
    client: *mut mcm_shm_client_t,
    out: *mut mcm_state_t,
) -> mcm_error_t {
    const F: &str = "mcm_shm_wait_state";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = args::out(out, F, "out")?;
            *o = (&h.client.wait_state()?).into();
            Ok(())
        })
    }
}

/// `mcm_shm_wait_state` with its own bound [s]. Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_wait_state_timeout(
    client: *mut mcm_shm_client_t,
    timeout_s: f64,
    out: *mut mcm_state_t,
) -> mcm_error_t {
    const F: &str = "mcm_shm_wait_state_timeout";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = args::out(out, F, "out")?;
            let wait = args::seconds(timeout_s, F, "timeout_s")?;
            *o = (&h.client.wait_state_timeout(wait)?).into();
            Ok(())
        })
    }
}

/// The newest state without waiting (it may be the one returned last). Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_latest(
    client: *mut mcm_shm_client_t,
    out: *mut mcm_state_t,
) -> mcm_error_t {
    const F: &str = "mcm_shm_latest";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            *args::out(out, F, "out")? = (&h.client.latest()).into();
            Ok(())
        })
    }
}

/// Enter HOLD (open to every client). Waits for the core's reply.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_hold(client: *mut mcm_shm_client_t) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe { call("mcm_shm_hold", client, |h| Ok(h.client.hold()?)) }
}

/// The core's number of axes and cycle period.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_info(
    client: *mut mcm_shm_client_t,
    out: *mut mcm_shm_info_t,
) -> mcm_error_t {
    const F: &str = "mcm_shm_info";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = args::out(out, F, "out")?;
            let i = h.client.info()?;
            *o = mcm_shm_info_t {
                num_axes: i.num_axes,
                period_s: i.period_s,
            };
            Ok(())
        })
    }
}

/// Home the axes (`options` NULL: all, default directions); returns when it has finished.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_calibrate(
    client: *mut mcm_shm_client_t,
    options: *const mcm_calibrate_t,
) -> mcm_error_t {
    const F: &str = "mcm_shm_calibrate";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            Ok(h.client.calibrate(args::calibrate(options, F)?)?)
        })
    }
}

/// `hold`, then `calibrate` only when an axis is not calibrated; `*calibrated` (may be NULL)
/// says whether it calibrated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_calibrate_if_needed(
    client: *mut mcm_shm_client_t,
    calibrated: *mut bool,
) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_shm_calibrate_if_needed", client, |h| {
            put(calibrated, h.client.calibrate_if_needed()?);
            Ok(())
        })
    }
}

/// Enter RELEASE.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_release(client: *mut mcm_shm_client_t) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe { call("mcm_shm_release", client, |h| Ok(h.client.release()?)) }
}

/// Enter PVT with points spaced `dt_s` seconds.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_pvt(client: *mut mcm_shm_client_t, dt_s: f64) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe { call("mcm_shm_pvt", client, |h| Ok(h.client.pvt(dt_s)?)) }
}

/// Enter TORQUE_CONTROL (`options` NULL: the defaults; `dt_status_s` is not used here).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_torque_control(
    client: *mut mcm_shm_client_t,
    options: *const mcm_control_options_t,
) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_shm_torque_control", client, |h| {
            let o = args::control_options(options);
            Ok(h.client.torque_control(TorqueControl {
                timeout_s: args::timeout(o.timeout_s),
                gravity_compensation: o.gravity_compensation,
            })?)
        })
    }
}

/// Set the six torques [Nm] without waiting (a refusal comes as an event). Real-time safe
/// (one small allocation inside iceoryx2's publisher).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_set_torques(
    client: *mut mcm_shm_client_t,
    torques: *const f64,
) -> mcm_error_t {
    const F: &str = "mcm_shm_set_torques";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            Ok(h.client.set_torques(six(torques, F, "torques")?)?)
        })
    }
}

/// Enter VELOCITY_CONTROL (`options` NULL: the defaults; only `timeout_s` is used).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_velocity_control(
    client: *mut mcm_shm_client_t,
    options: *const mcm_control_options_t,
) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_shm_velocity_control", client, |h| {
            let o = args::control_options(options);
            Ok(h.client.velocity_control(VelocityControl {
                timeout_s: args::timeout(o.timeout_s),
            })?)
        })
    }
}

/// Set the six velocities [deg/s] without waiting. Real-time safe (one small allocation
/// inside iceoryx2's publisher).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_set_velocities(
    client: *mut mcm_shm_client_t,
    velocities: *const f64,
) -> mcm_error_t {
    const F: &str = "mcm_shm_set_velocities";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            Ok(h.client.set_velocities(six(velocities, F, "velocities")?)?)
        })
    }
}

/// Move axis `axis` (1 to 6) to `target_deg` at `velocity_factor`; OK as the motion starts.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_move_axis(
    client: *mut mcm_shm_client_t,
    axis: u32,
    target_deg: f64,
    velocity_factor: f64,
) -> mcm_error_t {
    const F: &str = "mcm_shm_move_axis";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            Ok(h.client.move_axis(MoveAxis {
                axis: args::axis(axis, F)?,
                target_deg,
                velocity_factor,
            })?)
        })
    }
}

/// Move all axes together to the six `targets_deg`; `result` (may be NULL): the plan.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_move_all(
    client: *mut mcm_shm_client_t,
    targets_deg: *const f64,
    velocity_factor: f64,
    result: *mut mcm_move_all_result_t,
) -> mcm_error_t {
    const F: &str = "mcm_shm_move_all";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let p = h.client.move_all(MoveAll {
                targets_deg: six(targets_deg, F, "targets_deg")?,
                velocity_factor,
            })?;
            put(
                result,
                mcm_move_all_result_t {
                    velocities: p.velocities_deg_s,
                    longest: u32::from(p.longest.number()),
                    max_time_to_target: p.duration_s,
                },
            );
            Ok(())
        })
    }
}

/// Queue a batch of 1 to 1000 PVT points, whole or not at all.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_pvt_points(
    client: *mut mcm_shm_client_t,
    points: *const mcm_pvt_point_t,
    count: usize,
) -> mcm_error_t {
    const F: &str = "mcm_shm_pvt_points";
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

/// Take control of the arm's motion.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_take_control(client: *mut mcm_shm_client_t) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_shm_take_control", client, |h| {
            Ok(h.client.take_control()?)
        })
    }
}

/// Give up control; what this client drove ends in HOLD.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_release_control(client: *mut mcm_shm_client_t) -> mcm_error_t {
    // SAFETY: the header's contract.
    unsafe {
        call("mcm_shm_release_control", client, |h| {
            Ok(h.client.release_control()?)
        })
    }
}

/// The oldest event not taken yet (safety errors and refusals seen while reading states);
/// `*got` says whether `*out` was filled (its `message` lives until the next call here).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_next_event(
    client: *mut mcm_shm_client_t,
    out: *mut mcm_event_t,
    got: *mut bool,
) -> mcm_error_t {
    const F: &str = "mcm_shm_next_event";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let o = args::out(out, F, "out")?;
            let got = args::out(got, F, "got")?;
            *got = false;
            let Some(e) = h.client.next_event() else {
                return Ok(());
            };
            let (kind, code, axis, message) = match e {
                ShmEvent::SafetyError(e) => (
                    MCM_EVENT_SAFETY_ERROR,
                    e.reason.code().to_wire(),
                    e.reason.axis().map_or(0, |a| u32::from(a.number())),
                    format!("safety check tripped: {}", e.reason),
                ),
                ShmEvent::Refused(r) => {
                    let (reason, verb) = match r.outcome {
                        Outcome::Refused(reason) => (Some(reason), "refused"),
                        Outcome::Failed(reason) => (Some(reason), "failed"),
                        Outcome::Done(_) => (None, "answered"),
                    };
                    (
                        MCM_EVENT_COMMAND_ERROR,
                        reason.map_or(0, |r| r.code().to_wire()),
                        reason
                            .and_then(|r| r.axis())
                            .map_or(0, |a| u32::from(a.number())),
                        match reason {
                            Some(reason) => format!("{} {verb}: {reason}", r.kind),
                            None => format!("{} {verb}", r.kind),
                        },
                    )
                }
                ShmEvent::UnreadableSafetyError(e) => (
                    MCM_EVENT_NOTICE,
                    0,
                    0,
                    format!(
                        "the core's safety error record does not read ({e}); build the client from the same MCM version as the core"
                    ),
                ),
            };
            h.event_message = c_string(&message);
            *o = mcm_event_t {
                kind,
                code,
                axis,
                message: h.event_message.as_ptr(),
                status: mcm_status_t::default(),
            };
            *got = true;
            Ok(())
        })
    }
}

/// Read every state until `predicate(state, user)` is nonzero, at most `timeout_s`;
/// `MCM_ERR_NOT_REACHED` naming `what` after that. `state` (may be NULL): that state.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_wait_until(
    client: *mut mcm_shm_client_t,
    what: *const c_char,
    timeout_s: f64,
    predicate: mcm_state_predicate_fn,
    user: *mut c_void,
    state: *mut mcm_state_t,
) -> mcm_error_t {
    const F: &str = "mcm_shm_wait_until";
    // SAFETY: the header's contract.
    unsafe {
        call(F, client, |h| {
            let what = text(what, F, "what")?;
            let pred = predicate.ok_or_else(|| Fail::null(F, "predicate"))?;
            let wait = args::seconds(timeout_s, F, "timeout_s")?;
            let s = h.client.wait_until(what, wait, |s| {
                let c: mcm_state_t = s.into();
                // SAFETY: a C function with a valid state and the caller's `user`.
                pred(&c, user) != 0
            })?;
            put(state, (&s).into());
            Ok(())
        })
    }
}

/// The control loop (in the manner of libfranka): `callback(state, out, user)` is called with
/// every cycle's state and fills `out` (its `kind` preset from the mode: torques in
/// TORQUE_CONTROL, velocities in VELOCITY_CONTROL, the next point in PVT with `dt` one cycle);
/// the answer is sent at once, to be applied in the next cycle. The arm must be in one of those
/// modes with this client controlling it. Returns `MCM_OK` when the callback returned
/// `MCM_CONTROL_FINISH` (the mode is left as it is), else why the loop ended
/// (`MCM_ERR_MODE_LEFT`, `MCM_ERR_SAFETY_TRIP`, `MCM_ERR_OWNERSHIP_LOST`, `MCM_ERR_REFUSED`,
/// `MCM_ERR_NOT_CONTROLLING`, `MCM_ERR_TIMEOUT`, `MCM_ERR_ARGUMENT` for an unknown
/// `out->kind`). `summary` (may be NULL) is filled either way: cycles, missed, answers applied
/// in the next cycle. The running loop allocates only inside iceoryx2's publisher, once per
/// answer sent.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_control(
    client: *mut mcm_shm_client_t,
    callback: mcm_control_fn,
    user: *mut c_void,
    summary: *mut mcm_control_summary_t,
) -> mcm_error_t {
    const F: &str = "mcm_shm_control";
    // SAFETY: the header's contract.
    unsafe {
        put(summary, mcm_control_summary_t::default());
        call(F, client, |h| {
            let cb = callback.ok_or_else(|| Fail::null(F, "callback"))?;
            let mut bad_kind = None;
            let result = h.client.control(|s| {
                let state: mcm_state_t = s.into();
                let kind = match Mode::try_from(s.mode) {
                    Ok(Mode::VelocityControl) => MCM_OUTPUT_VELOCITIES,
                    Ok(Mode::Pvt) => MCM_OUTPUT_PVT,
                    _ => MCM_OUTPUT_TORQUES,
                };
                let mut o = mcm_control_output_t {
                    kind,
                    ..Default::default()
                };
                // SAFETY: a C function with valid pointers and the caller's `user`.
                if cb(&state, &mut o, user) != 0 {
                    return ControlOutput::Finish;
                }
                match o.kind {
                    MCM_OUTPUT_TORQUES => ControlOutput::Torques(o.values),
                    MCM_OUTPUT_VELOCITIES => ControlOutput::Velocities(o.values),
                    MCM_OUTPUT_PVT => ControlOutput::Pvt(PvtPoint {
                        position_deg: o.values,
                        velocity_deg_s: o.pvt_velocities,
                    }),
                    k => {
                        bad_kind = Some(k);
                        ControlOutput::Finish
                    }
                }
            });
            let (sum, end) = match result {
                Ok(s) => (s, None),
                Err(e) => (e.summary, Some(e)),
            };
            put(summary, (&sum).into());
            if let Some(k) = bad_kind {
                return Err(Fail::new(
                    mcm_error_t::MCM_ERR_ARGUMENT,
                    format!(
                        "{F}: the callback set `out->kind` = {k}; expected MCM_OUTPUT_TORQUES (1), MCM_OUTPUT_VELOCITIES (2) or MCM_OUTPUT_PVT (3)"
                    ),
                ));
            }
            match end {
                None => Ok(()),
                Some(e) => {
                    let (code, reject) = control_end(&e.end);
                    Err(Fail {
                        code,
                        reject,
                        message: e.to_string(),
                    })
                }
            }
        })
    }
}
