use super::*;
use std::collections::HashSet;
use std::ffi::CStr;
use std::fmt::Write;

#[path = "../../tests/common/mod.rs"]
mod common;

fn name(n: u32) -> &'static str {
    // SAFETY: mcm_error_code_name returns static NUL-terminated strings.
    unsafe { CStr::from_ptr(mcm_error_code_name(n)) }
        .to_str()
        .unwrap()
}

#[test]
fn every_code_has_its_number_and_its_name() {
    let mut numbers = HashSet::new();
    for c in ErrorCode::ALL {
        let n = number(*c);
        assert!(numbers.insert(n), "{c}: number {n} twice");
        assert_eq!(name(n), c.as_str());
        assert_eq!(by_number(n), Some(*c));
        match c.reject_code() {
            Some(r) => assert_eq!(n, r.to_wire(), "{c}: its shared-memory number"),
            None => assert!(n >= GATEWAY_FROM, "{c}: {n}"),
        }
    }
    assert_eq!(name(0), "none");
    assert_eq!(name(99), "unknown");
    assert_eq!(name(GATEWAY_FROM + 1000), "unknown");
}

/// The generated source of `capi/src/code/c_enum.rs`: `mcm_error_code_t` names every code of
/// the table, in its order, with its [`number`], and nothing else.
fn render() -> String {
    let mut out = String::from(
        "//! GENERATED from the table of codes in `shared/src/error_code.rs` (`ErrorCode::ALL`,
//! numbered by `capi/src/code.rs`'s `number`); do not edit by hand:
//! `MCM_UPDATE_CAPI=1 cargo test -p mcm-capi --lib code::tests` writes it anew.
//!
//! The C enum of the MCM's error codes, written out for cbindgen (which does not expand
//! macros) and so into `include/mcm/mcm.h`.

/// The MCM's code of a failed call (`mcm_*_last_reject`), of an event and of
/// `mcm_state_t.last_error` (a check): the protocol's `error_code`, as a number.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum mcm_error_code_t {
    /// No code (a call that did not fail, or a failure the MCM did not answer).
    MCM_CODE_NONE = 0,
",
    );
    for c in ErrorCode::ALL {
        let _ = writeln!(
            out,
            "    MCM_CODE_{} = {},",
            c.as_str().to_uppercase(),
            number(*c)
        );
    }
    out.push_str("}\n");
    out
}

#[test]
fn the_checked_in_enum_is_what_the_table_generates() {
    common::check_generated(
        "capi/src/code/c_enum.rs",
        "the table of shared/src/error_code.rs",
        &render(),
        "MCM_UPDATE_CAPI",
        "cargo test -p mcm-capi --lib code::tests",
    );
}
