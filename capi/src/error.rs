//! Result codes, the failure of one call ([`Fail`]), where its message is kept, and the guard
//! that keeps panics from crossing the ABI. Not real-time code except the success path of
//! [`guard`] (no allocation there).

use mcm_client::mcm_shared::reply::{Outcome, Reason};
use mcm_client::shm::{ControlEnd, OpenError, RequestError, SendError, WaitError, WaitUntilError};
use mcm_client::tcp::{Error as TcpError, ErrorKind};
use std::cell::RefCell;
use std::ffi::{CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// What a call of the C API ended with. `MCM_OK` (0) is success; every other value says why
/// not, and the message of the failure is in `mcm_last_error()` (and the handle's
/// `mcm_*_last_error`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum mcm_error_t {
    /// Success.
    MCM_OK = 0,
    /// A required pointer argument was NULL.
    MCM_ERR_NULL_POINTER = 1,
    /// An argument this library refuses before sending anything (not UTF-8, an axis outside
    /// 1 to 6, no PVT points, more than 1000 over shared memory, an unknown output kind).
    MCM_ERR_ARGUMENT = 2,
    /// TCP: the MCM cannot be reached at that address.
    MCM_ERR_CONNECT = 3,
    /// Shared memory: the MCM instance is not running on this computer.
    MCM_ERR_NOT_RUNNING = 4,
    /// Shared memory: the running MCM is of another version than this library.
    MCM_ERR_INCOMPATIBLE = 5,
    /// The connection broke (TCP) or an iceoryx2 step failed (shared memory).
    MCM_ERR_IO = 6,
    /// TCP: the MCM closed the connection (its last notice is the message).
    MCM_ERR_CLOSED = 7,
    /// TCP: an earlier call found the connection broken; call `mcm_tcp_reconnect`.
    MCM_ERR_NOT_CONNECTED = 8,
    /// Shared memory: no new state within the wait (the real-time core is not publishing).
    MCM_ERR_TIMEOUT = 9,
    /// The MCM refused the command: nothing changed (reject code in `mcm_*_last_reject`).
    MCM_ERR_REFUSED = 10,
    /// The MCM accepted the command, then it failed while running (e.g. a calibration).
    MCM_ERR_FAILED = 11,
    /// No answer in time: the command may or may not have been executed; read the state.
    MCM_ERR_OUTCOME_UNKNOWN = 12,
    /// TCP: the gateway refused the command's arguments or the access rules refused it.
    MCM_ERR_INVALID = 13,
    /// An answer this library cannot read (an MCM of another version).
    MCM_ERR_PROTOCOL = 14,
    /// `wait_until`: the condition did not hold within the time.
    MCM_ERR_NOT_REACHED = 15,
    /// Control loop: the mode changed (timeout fallback, `hold` from anyone).
    MCM_ERR_MODE_LEFT = 16,
    /// Control loop: a safety check tripped (the message names it).
    MCM_ERR_SAFETY_TRIP = 17,
    /// Control loop: another client controls the arm now, or nobody does.
    MCM_ERR_OWNERSHIP_LOST = 18,
    /// Control loop: the arm is not in TORQUE_CONTROL, VELOCITY_CONTROL or PVT.
    MCM_ERR_NOT_CONTROLLING = 19,
    /// A bug of this library was caught (a Rust panic); close the handle.
    MCM_ERR_PANIC = 20,
}

use mcm_error_t::*;

/// The failure of one call: its code, the MCM's reject code (0: none) and its message.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Fail {
    pub code: mcm_error_t,
    pub reject: u32,
    pub message: String,
}

impl Fail {
    pub(crate) fn new(code: mcm_error_t, message: impl Into<String>) -> Fail {
        Fail {
            code,
            reject: 0,
            message: message.into(),
        }
    }

    pub(crate) fn null(function: &str, argument: &str) -> Fail {
        Fail::new(
            MCM_ERR_NULL_POINTER,
            format!("{function}: argument `{argument}` is NULL; pass a valid pointer"),
        )
    }
}

impl From<TcpError> for Fail {
    fn from(e: TcpError) -> Fail {
        let message = e.to_string();
        let (code, reject) = match &e {
            TcpError::Mcm(m) => (
                match m.kind {
                    ErrorKind::Refused => MCM_ERR_REFUSED,
                    ErrorKind::Failed => MCM_ERR_FAILED,
                    ErrorKind::OutcomeUnknown => MCM_ERR_OUTCOME_UNKNOWN,
                    ErrorKind::Invalid => MCM_ERR_INVALID,
                },
                m.code.map_or(0, crate::code::number),
            ),
            TcpError::Connect { .. } => (MCM_ERR_CONNECT, 0),
            TcpError::Io { .. } => (MCM_ERR_IO, 0),
            TcpError::Closed { .. } => (MCM_ERR_CLOSED, 0),
            TcpError::NotConnected => (MCM_ERR_NOT_CONNECTED, 0),
            TcpError::Timeout { .. } => (MCM_ERR_OUTCOME_UNKNOWN, 0),
            TcpError::Protocol { .. } => (MCM_ERR_PROTOCOL, 0),
            TcpError::Argument { .. } => (MCM_ERR_ARGUMENT, 0),
            TcpError::NotReached { .. } => (MCM_ERR_NOT_REACHED, 0),
        };
        Fail {
            code,
            reject,
            message,
        }
    }
}

impl From<OpenError> for Fail {
    fn from(e: OpenError) -> Fail {
        let code = match &e {
            OpenError::InstanceName(_) => MCM_ERR_ARGUMENT,
            OpenError::NotRunning { .. } => MCM_ERR_NOT_RUNNING,
            OpenError::Incompatible { .. } => MCM_ERR_INCOMPATIBLE,
            OpenError::NodeName { .. }
            | OpenError::Node { .. }
            | OpenError::Service { .. }
            | OpenError::Reader { .. }
            | OpenError::Publisher { .. }
            | OpenError::Listener { .. } => MCM_ERR_IO,
        };
        Fail::new(code, e.to_string())
    }
}

impl From<SendError> for Fail {
    fn from(e: SendError) -> Fail {
        Fail::new(MCM_ERR_IO, e.to_string())
    }
}

fn wait_code(e: &WaitError) -> mcm_error_t {
    match e {
        WaitError::Timeout { .. } => MCM_ERR_TIMEOUT,
        WaitError::Listener { .. } => MCM_ERR_IO,
    }
}

impl From<WaitError> for Fail {
    fn from(e: WaitError) -> Fail {
        Fail::new(wait_code(&e), e.to_string())
    }
}

impl From<RequestError> for Fail {
    fn from(e: RequestError) -> Fail {
        let code = match &e {
            RequestError::Send(_) => MCM_ERR_IO,
            RequestError::Wait(w) => wait_code(w),
            RequestError::Refused { .. } => MCM_ERR_REFUSED,
            RequestError::Failed { .. } => MCM_ERR_FAILED,
            RequestError::OutcomeUnknown { .. } => MCM_ERR_OUTCOME_UNKNOWN,
            RequestError::Undecodable { .. } => MCM_ERR_PROTOCOL,
            RequestError::Argument { .. } => MCM_ERR_ARGUMENT,
        };
        Fail {
            code,
            reject: e.reason().map_or(0, |r| r.code().to_wire()),
            message: e.to_string(),
        }
    }
}

impl From<WaitUntilError> for Fail {
    fn from(e: WaitUntilError) -> Fail {
        let code = match &e {
            WaitUntilError::Wait(w) => wait_code(w),
            WaitUntilError::NotReached { .. } => MCM_ERR_NOT_REACHED,
        };
        Fail::new(code, e.to_string())
    }
}

/// The code and reject code of a control loop's end (its message is the loop's error).
pub(crate) fn control_end(end: &ControlEnd) -> (mcm_error_t, u32) {
    match end {
        ControlEnd::ModeLeft { .. } => (MCM_ERR_MODE_LEFT, 0),
        ControlEnd::SafetyTrip(e) => (MCM_ERR_SAFETY_TRIP, e.reason.code().to_wire()),
        ControlEnd::OwnershipLost { .. } => (MCM_ERR_OWNERSHIP_LOST, 0),
        ControlEnd::Refused(r) => {
            let (code, reason, _) = not_done(r.outcome);
            (code, reason.map_or(0, |r| r.code().to_wire()))
        }
        ControlEnd::NotControlling(_) => (MCM_ERR_NOT_CONTROLLING, 0),
        ControlEnd::Send(_) => (MCM_ERR_IO, 0),
        ControlEnd::Wait(e) => (wait_code(e), 0),
        ControlEnd::UnreadableSafetyError(_) => (MCM_ERR_PROTOCOL, 0),
    }
}

/// What the core's answer `outcome` to a request that was not answered as expected says in
/// the C API: its code, its reason (none for an answer of another kind) and the verb of its
/// message ("refused", "failed", "answered").
pub(crate) fn not_done(outcome: Outcome) -> (mcm_error_t, Option<Reason>, &'static str) {
    match outcome {
        Outcome::Refused(reason) => (MCM_ERR_REFUSED, Some(reason), "refused"),
        Outcome::Failed(reason) => (MCM_ERR_FAILED, Some(reason), "failed"),
        Outcome::Done(_) => (MCM_ERR_PROTOCOL, None, "answered"),
    }
}

/// A message as a C string (a NUL inside would end it early: replaced by a space).
pub(crate) fn c_string(message: &str) -> CString {
    CString::new(message.replace('\0', " ")).unwrap_or_default()
}

/// Where one handle keeps the failure of its last failed call.
#[derive(Debug, Default)]
pub(crate) struct LastError {
    pub message: CString,
    pub reject: u32,
}

impl LastError {
    pub(crate) fn set(&mut self, f: &Fail) {
        self.message = c_string(&f.message);
        self.reject = f.reject;
    }
}

thread_local! {
    static THREAD_ERROR: RefCell<(CString, u32)> = RefCell::new((CString::default(), 0));
}

fn set_thread_error(f: &Fail) {
    THREAD_ERROR.with(|e| *e.borrow_mut() = (c_string(&f.message), f.reject));
}

/// Run one entry point: a panic becomes `MCM_ERR_PANIC`, a failure is recorded in the
/// calling thread (and by `record` in the handle) and returned as its code. On success nothing
/// is allocated.
pub(crate) fn guard(
    function: &str,
    record: impl FnOnce(&Fail),
    body: impl FnOnce() -> Result<(), Fail>,
) -> mcm_error_t {
    let fail = match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => return MCM_OK,
        Ok(Err(f)) => f,
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".into());
            Fail::new(
                MCM_ERR_PANIC,
                format!(
                    "{function}: internal error of the MCM C library ({what}); close this handle and report it"
                ),
            )
        }
    };
    // Recording must not unwind into C either.
    let _ = catch_unwind(AssertUnwindSafe(|| {
        set_thread_error(&fail);
        record(&fail);
    }));
    fail.code
}

/// A client handle of the C API: where a failed call on it keeps its message.
pub(crate) trait Handle {
    fn last_error(&mut self) -> &mut LastError;
}

/// Run `body` on the handle `h` (NULL refused), recording a failure in it as [`guard`] does.
/// Allocates nothing when `body` succeeds.
///
/// # Safety
/// `h` is NULL or a live handle of its connect function, used by its thread only.
pub(crate) unsafe fn call<H: Handle>(
    function: &str,
    h: *mut H,
    body: impl FnOnce(&mut H) -> Result<(), Fail>,
) -> mcm_error_t {
    // SAFETY: the caller's promise.
    let Some(h) = (unsafe { h.as_mut() }) else {
        return guard(function, |_| {}, || Err(Fail::null(function, "client")));
    };
    let mut failed = None;
    let code = guard(function, |f| failed = Some(f.clone()), || body(h));
    if let Some(f) = failed {
        h.last_error().set(&f);
    }
    code
}

/// Drop the handle `h` (NULL: nothing); a panic while dropping stays on this side.
///
/// # Safety
/// `h` is NULL or a handle from `Box::into_raw` of its connect function, closed once.
pub(crate) unsafe fn close<H>(h: *mut H) {
    if !h.is_null() {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: the caller's promise.
            drop(unsafe { Box::from_raw(h) })
        }));
    }
}

/// The message of the last failed call on the calling thread (any function, also the connect
/// functions), or "" when none failed yet. The pointer stays valid until the next failing call
/// on this thread. Real-time safe.
#[unsafe(no_mangle)]
pub extern "C" fn mcm_last_error() -> *const c_char {
    THREAD_ERROR
        .try_with(|e| e.borrow().0.as_ptr())
        .unwrap_or(c"".as_ptr())
}

/// The MCM's error code of the last failed call on the calling thread (an `mcm_error_code_t`:
/// 0 none, else a code `mcm_error_code_name` names, e.g. 16 busy). Real-time safe.
#[unsafe(no_mangle)]
pub extern "C" fn mcm_last_reject() -> u32 {
    THREAD_ERROR.try_with(|e| e.borrow().1).unwrap_or(0)
}

#[cfg(test)]
mod tests;
