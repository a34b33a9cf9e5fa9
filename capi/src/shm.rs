//! `mcm_shm_*`: the real-time core's shared-memory services (mcm-client's `shm::ShmClient`),
//! with the control loop. `mcm_shm_wait_state`, `mcm_shm_latest`, `mcm_shm_set_torques`,
//! `mcm_shm_set_velocities`, the accessors and the running loop of `mcm_shm_control` are
//! real-time code (no lock, no blocking; a command sent makes one allocation inside iceoryx2's
//! publisher, see the crate's documentation); the commands that wait for a reply are not.
//!
//! The handle and what is particular to this transport live here (connect, close, the last
//! error, events, `wait_until`, the control loop); the commands' functions are generated from
//! one list for both transports (`commands.rs`).

use crate::convert::{self, put, text};
use crate::error::{
    Fail, Handle, LastError, c_string, call, close, control_end, guard, mcm_error_t, not_done,
};
use crate::types::*;
use mcm_client::Mode;
use mcm_client::mcm_shared::command::PvtPoint;
use mcm_client::shm::{ControlOutput, ShmClient, ShmEvent};
use std::ffi::{CString, c_char, c_void};

/// A client of the MCM's shared-memory services (opaque; `mcm_shm_connect`,
/// `mcm_shm_close`). Bound to the thread that created it.
pub struct mcm_shm_client_t {
    pub(crate) client: ShmClient,
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
            let slot = unsafe { convert::out(out, F, "out") }?;
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

/// The MCM's error code of the last failed call on this handle (an `mcm_error_code_t`, 0:
/// none). Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_shm_last_reject(client: *const mcm_shm_client_t) -> u32 {
    // SAFETY: NULL or a live handle.
    unsafe { client.as_ref() }.map_or(0, |h| h.last.reject)
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
            let o = convert::out(out, F, "out")?;
            let got = convert::out(got, F, "got")?;
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
                    let (_, reason, verb) = not_done(r.outcome);
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
            let wait = convert::seconds(timeout_s, F, "timeout_s")?;
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
