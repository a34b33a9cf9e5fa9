//! The MCM's error codes in C (`docs/protocol.md`, "Error codes"): `mcm_error_code_t` names
//! every code of `mcm_shared::error_code` with its number, and [`mcm_error_code_name`] its name.
//! The number of a reason of the real-time core is its shared-memory number (1 to 99); the
//! gateway's own codes are numbered from 100 in the order of the table. The enum is written
//! here for cbindgen; its test checks it, in the generated header, against the table.
//! Real-time safe: no allocation.

use mcm_client::ErrorCode;
use std::ffi::c_char;

/// The MCM's code of a failed call (`mcm_*_last_reject`), of an event and of
/// `mcm_state_t.last_error` (a check): the protocol's `error_code`, as a number.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum mcm_error_code_t {
    /// No code (a call that did not fail, or a failure the MCM did not answer).
    MCM_CODE_NONE = 0,
    MCM_CODE_WRONG_MODE = 1,
    MCM_CODE_NOT_CALIBRATED = 2,
    MCM_CODE_EMERGENCY_STOP = 3,
    MCM_CODE_DRIVE_DISCONNECTED = 4,
    MCM_CODE_DRIVE_FAULT = 5,
    MCM_CODE_OUT_OF_RANGE = 6,
    MCM_CODE_NOT_AVAILABLE = 7,
    MCM_CODE_NOT_SIMULATED = 8,
    MCM_CODE_QUEUE_FULL = 9,
    MCM_CODE_POSITION_LIMIT = 10,
    MCM_CODE_VELOCITY_LIMIT = 11,
    MCM_CODE_BRAKING_DISTANCE = 12,
    MCM_CODE_FOLLOWING_ERROR = 13,
    MCM_CODE_CALIBRATION_FAILED = 14,
    MCM_CODE_ABORTED = 15,
    MCM_CODE_BUSY = 16,
    MCM_CODE_PVT_POINT = 17,
    MCM_CODE_UNREACHABLE = 18,
    MCM_CODE_NOT_OWNER = 19,
    MCM_CODE_SHUTTING_DOWN = 20,
    MCM_CODE_OVERLOAD = 21,
    MCM_CODE_INVALID_JSON = 100,
    MCM_CODE_INVALID_COMMAND = 101,
    MCM_CODE_UNKNOWN_COMMAND = 102,
    MCM_CODE_UNKNOWN_ARGUMENT = 103,
    MCM_CODE_MISSING_ARGUMENT = 104,
    MCM_CODE_INVALID_ARGUMENT = 105,
    MCM_CODE_LINE_TOO_LONG = 106,
    MCM_CODE_LINE_TIMEOUT = 107,
    MCM_CODE_IDLE_TIMEOUT = 108,
    MCM_CODE_EVICTED = 109,
    MCM_CODE_TOO_MANY_CONNECTIONS = 110,
    MCM_CODE_TOO_MANY_REQUESTS = 111,
    MCM_CODE_NETWORK_REFUSED = 112,
    MCM_CODE_NOT_AUTHENTICATED = 113,
    MCM_CODE_WRONG_SECRET = 114,
    MCM_CODE_REMOTE_SIM_REFUSED = 115,
    MCM_CODE_CORE_UNAVAILABLE = 116,
    MCM_CODE_OUTCOME_UNKNOWN = 117,
    MCM_CODE_VERSION_MISMATCH = 118,
    MCM_CODE_CORE_STOPPING = 119,
    MCM_CODE_CORE_STOPPED = 120,
    MCM_CODE_CORE_VANISHED = 121,
    MCM_CODE_GATEWAY_STOPPING = 122,
    MCM_CODE_EVENTS_LOST = 123,
    MCM_CODE_INTERNAL_ERROR = 124,
}

/// The first number of the gateway's own codes.
const GATEWAY_FROM: u32 = 100;

/// The C number of `code`.
pub(crate) fn number(code: ErrorCode) -> u32 {
    match code.reject_code() {
        Some(r) => r.to_wire(),
        None => {
            let core = ErrorCode::ALL
                .iter()
                .filter(|c| c.reject_code().is_some())
                .count();
            let at = ErrorCode::ALL.iter().position(|c| *c == code).unwrap_or(0);
            GATEWAY_FROM + (at - core.min(at)) as u32
        }
    }
}

/// The code numbered `n` (0 and unknown numbers: none).
pub(crate) fn by_number(n: u32) -> Option<ErrorCode> {
    ErrorCode::ALL.iter().copied().find(|c| number(*c) == n)
}

/// The longest name, with its NUL.
const NAME_LEN: usize = 32;

/// Every code's name, NUL-terminated, in the order of [`ErrorCode::ALL`]; built when the
/// library is compiled, so that naming a code allocates nothing.
static NAMES: [[u8; NAME_LEN]; ErrorCode::ALL.len()] = names();

const fn names() -> [[u8; NAME_LEN]; ErrorCode::ALL.len()] {
    let mut out = [[0u8; NAME_LEN]; ErrorCode::ALL.len()];
    let mut i = 0;
    while i < ErrorCode::ALL.len() {
        let name = ErrorCode::ALL[i].as_str().as_bytes();
        assert!(
            name.len() < NAME_LEN,
            "an error code's name is too long for NAMES"
        );
        let mut k = 0;
        while k < name.len() {
            out[i][k] = name[k];
            k += 1;
        }
        i += 1;
    }
    out
}

/// The name of the code numbered `code` (`mcm_error_code_t`, `mcm_*_last_reject`, events,
/// `mcm_state_t.last_error.code`), e.g. "busy", "not_owner", "invalid_json"; "none" for 0,
/// "unknown" for a number this library does not know (a static string). Real-time safe.
#[unsafe(no_mangle)]
pub extern "C" fn mcm_error_code_name(code: u32) -> *const c_char {
    if code == 0 {
        return c"none".as_ptr();
    }
    match by_number(code).and_then(|c| ErrorCode::ALL.iter().position(|x| *x == c)) {
        Some(i) => NAMES[i].as_ptr().cast(),
        None => c"unknown".as_ptr(),
    }
}

#[cfg(test)]
mod tests;
