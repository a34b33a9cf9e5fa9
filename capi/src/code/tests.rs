use super::*;
use std::collections::HashSet;
use std::ffi::CStr;

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

/// The C enum, as cbindgen writes it into the header, names every code of the table with its
/// number, and nothing else.
#[test]
fn the_headers_enum_is_the_table_of_codes() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/include/mcm/mcm.h");
    let header = std::fs::read_to_string(path).expect("include/mcm/mcm.h");
    let have: Vec<&str> = header
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("MCM_CODE_"))
        .collect();
    let mut want = vec!["MCM_CODE_NONE = 0,".to_string()];
    want.extend(
        ErrorCode::ALL
            .iter()
            .map(|c| format!("MCM_CODE_{} = {},", c.as_str().to_uppercase(), number(*c))),
    );
    assert_eq!(
        have, want,
        "mcm_error_code_t (capi/src/code.rs) differs from shared/src/error_code.rs; correct it, \
         then `MCM_UPDATE_HEADER=1 cargo test -p mcm-capi --test header`"
    );
}
