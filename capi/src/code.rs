//! The MCM's error codes in C (`docs/protocol.md`, "Error codes"): `mcm_error_code_t` names
//! every code of `mcm_shared::error_code` with its number, and [`mcm_error_code_name`] its name.
//! The number of a reason of the real-time core is its shared-memory number (1 to 99); the
//! gateway's own codes are numbered from 100 in the order of the table ([`number`]). The enum
//! is generated from the table and [`number`] into `code/c_enum.rs` (cbindgen reads source and
//! does not expand macros); its test fails while that file is stale:
//! `MCM_UPDATE_CAPI=1 cargo test -p mcm-capi --lib code::tests` writes it anew.
//! Real-time safe: no allocation.

// Generated (the test `code::tests`): the C enum of the codes.
#[rustfmt::skip]
mod c_enum;

pub use c_enum::mcm_error_code_t;
use mcm_client::ErrorCode;
use std::ffi::c_char;

/// The first number of the gateway's own codes.
const GATEWAY_FROM: u32 = 100;

/// The C number of `code`. C programs are compiled against these numbers (the enum of
/// `code/c_enum.rs` is generated from them): a new gateway code goes at the end of the table,
/// where it renumbers none of the others.
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
