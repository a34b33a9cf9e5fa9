//! The C header `include/mcm/mcm.h` is what cbindgen generates from this crate now: a change of
//! the API that did not regenerate it fails here (and so in CI). To write it anew:
//! `MCM_UPDATE_HEADER=1 cargo test -p mcm-capi --test header`; that run writes the header and
//! says what changed (on stderr, past the output capture) instead of comparing (refused when
//! `CI` is set: CI always compares).

mod common;

use std::path::Path;

#[test]
fn the_checked_in_header_is_what_cbindgen_generates() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header")
        .write(&mut generated);
    let generated = String::from_utf8(generated).expect("UTF-8");
    common::check_generated(
        "capi/include/mcm/mcm.h",
        "cbindgen from capi/src",
        &generated,
        "MCM_UPDATE_HEADER",
        "cargo test -p mcm-capi --test header",
    );
    // The header declares what the C++ layer and the examples use.
    for name in [
        "mcm_shm_control",
        "mcm_tcp_connect",
        "typedef struct mcm_state_t",
        "MCM_ERR_PANIC",
    ] {
        assert!(generated.contains(name), "{name} is not in the header");
    }
}
