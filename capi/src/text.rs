//! Names of the codes as static C strings (real-time safe: no allocation).

use crate::error::mcm_error_t::{self, *};
use mcm_client::Mode;
use std::ffi::{CStr, c_char};

/// The name of a result code, e.g. "MCM_ERR_REFUSED" (a static string).
#[unsafe(no_mangle)]
pub extern "C" fn mcm_error_name(code: mcm_error_t) -> *const c_char {
    let s: &'static CStr = match code {
        MCM_OK => c"MCM_OK",
        MCM_ERR_NULL_POINTER => c"MCM_ERR_NULL_POINTER",
        MCM_ERR_ARGUMENT => c"MCM_ERR_ARGUMENT",
        MCM_ERR_CONNECT => c"MCM_ERR_CONNECT",
        MCM_ERR_NOT_RUNNING => c"MCM_ERR_NOT_RUNNING",
        MCM_ERR_INCOMPATIBLE => c"MCM_ERR_INCOMPATIBLE",
        MCM_ERR_IO => c"MCM_ERR_IO",
        MCM_ERR_CLOSED => c"MCM_ERR_CLOSED",
        MCM_ERR_NOT_CONNECTED => c"MCM_ERR_NOT_CONNECTED",
        MCM_ERR_TIMEOUT => c"MCM_ERR_TIMEOUT",
        MCM_ERR_REFUSED => c"MCM_ERR_REFUSED",
        MCM_ERR_FAILED => c"MCM_ERR_FAILED",
        MCM_ERR_OUTCOME_UNKNOWN => c"MCM_ERR_OUTCOME_UNKNOWN",
        MCM_ERR_INVALID => c"MCM_ERR_INVALID",
        MCM_ERR_PROTOCOL => c"MCM_ERR_PROTOCOL",
        MCM_ERR_NOT_REACHED => c"MCM_ERR_NOT_REACHED",
        MCM_ERR_MODE_LEFT => c"MCM_ERR_MODE_LEFT",
        MCM_ERR_SAFETY_TRIP => c"MCM_ERR_SAFETY_TRIP",
        MCM_ERR_OWNERSHIP_LOST => c"MCM_ERR_OWNERSHIP_LOST",
        MCM_ERR_NOT_CONTROLLING => c"MCM_ERR_NOT_CONTROLLING",
        MCM_ERR_PANIC => c"MCM_ERR_PANIC",
    };
    s.as_ptr()
}

/// The name of an operating mode (`mcm_state_t.mode`, `mcm_status_t.mode`), e.g. "HOLD";
/// "UNKNOWN" for a number this library does not know (a static string).
#[unsafe(no_mangle)]
pub extern "C" fn mcm_mode_name(mode: u32) -> *const c_char {
    static NAMES: [&CStr; 8] = [
        c"OFF",
        c"ERROR",
        c"HOLD",
        c"RELEASE",
        c"TORQUE_CONTROL",
        c"PVT",
        c"CALIBRATION",
        c"VELOCITY_CONTROL",
    ];
    match Mode::try_from(mode) {
        Ok(m) => NAMES[m.to_wire() as usize].as_ptr(),
        Err(_) => c"UNKNOWN".as_ptr(),
    }
}

/// The name of an error code (`mcm_*_last_reject`, events, `mcm_state_t.last_error.code`):
/// the same as `mcm_error_code_name`, e.g. "busy", "none" for 0, "unknown" for a number this
/// library does not know (a static string).
#[unsafe(no_mangle)]
pub extern "C" fn mcm_reject_name(code: u32) -> *const c_char {
    crate::code::mcm_error_code_name(code)
}

#[cfg(test)]
mod tests;
