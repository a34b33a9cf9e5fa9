//! `mcm_tcp_*`: the JSON protocol over TCP (mcm-client's `tcp::TcpClient`), blocking, every
//! call bounded by a timeout. Not real-time code: calls allocate and wait on the network.
//!
//! The handle and what is particular to this transport live here (connect, close, the last
//! error, events, `wait_until`); the commands' functions are generated from one list for both
//! transports (`commands.rs`).

use crate::convert::{self, put, text};
use crate::error::{Fail, Handle, LastError, c_string, call, close, guard, mcm_error_t};
use crate::types::*;
use mcm_client::tcp::{Event, TcpClient};
use std::ffi::{CString, c_char, c_void};

/// A connection to the MCM's JSON port (opaque; `mcm_tcp_connect`, `mcm_tcp_close`).
pub struct mcm_tcp_client_t {
    pub(crate) client: TcpClient,
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
            let slot = unsafe { convert::out(out, F, "out") }?;
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

/// The MCM's error code of the last failed call on this handle (an `mcm_error_code_t`, 0:
/// none or a code this library does not know). Real-time safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mcm_tcp_last_reject(client: *const mcm_tcp_client_t) -> u32 {
    // SAFETY: NULL or a live handle.
    unsafe { client.as_ref() }.map_or(0, |h| h.last.reject)
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
            let o = convert::out(out, F, "out")?;
            let got = convert::out(got, F, "got")?;
            *got = false;
            let Some(e) = h
                .client
                .next_event(convert::seconds(timeout_s, F, "timeout_s")?)?
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
                    ev.code = m.code.map_or(0, crate::code::number);
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
            let wait = convert::seconds(timeout_s, F, "timeout_s")?;
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
