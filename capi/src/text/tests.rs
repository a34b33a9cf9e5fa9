use super::*;
use mcm_client::RejectCode;

fn text(p: *const c_char) -> &'static str {
    // SAFETY: the functions above return static NUL-terminated strings.
    unsafe { CStr::from_ptr(p) }.to_str().unwrap()
}

#[test]
fn names_match_the_contract_crate() {
    for m in Mode::ALL {
        assert_eq!(text(mcm_mode_name(m.to_wire())), m.as_str());
    }
    for c in RejectCode::ALL {
        assert_eq!(text(mcm_reject_name(c.to_wire())), c.as_str());
    }
    assert_eq!(text(mcm_mode_name(99)), "UNKNOWN");
    assert_eq!(text(mcm_reject_name(99)), "unknown");
    assert_eq!(text(mcm_error_name(MCM_ERR_REFUSED)), "MCM_ERR_REFUSED");
}
