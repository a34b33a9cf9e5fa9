//! The C header `include/mcm/mcm.h` is what cbindgen generates from this crate now: a change of
//! the API that did not regenerate it fails here (and so in CI). To write it anew:
//! `MCM_UPDATE_HEADER=1 cargo test -p mcm-capi --test header`; that run writes the header and
//! says what changed (on stderr, past the output capture) instead of comparing.

use std::io::Write;
use std::path::Path;

/// Where `old` and `new` first differ (1-based line) and their lengths, for a message.
fn difference(old: &str, new: &str) -> String {
    let (a, b): (Vec<&str>, Vec<&str>) = (old.lines().collect(), new.lines().collect());
    match (0..a.len().max(b.len())).find(|&i| a.get(i) != b.get(i)) {
        None => "the same lines".to_string(),
        Some(i) => format!(
            "first difference at line {}: {:?} became {:?}; {} lines became {}",
            i + 1,
            a.get(i).unwrap_or(&"(end of file)"),
            b.get(i).unwrap_or(&"(end of file)"),
            a.len(),
            b.len()
        ),
    }
}

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
    let path = dir.join("include/mcm/mcm.h");
    let checked_in = std::fs::read_to_string(&path).unwrap_or_default();
    if std::env::var_os("MCM_UPDATE_HEADER").is_some() {
        // Update mode: write, and say what changed; there is nothing to compare afterwards.
        let news = if checked_in == generated {
            "unchanged".to_string()
        } else {
            std::fs::write(&path, &generated).expect("write include/mcm/mcm.h");
            format!("written: {}", difference(&checked_in, &generated))
        };
        let _ = writeln!(
            std::io::stderr(),
            "MCM_UPDATE_HEADER: capi/include/mcm/mcm.h {news}; not compared (run again without \
             MCM_UPDATE_HEADER to check it)"
        );
    } else {
        assert!(
            checked_in == generated,
            "capi/include/mcm/mcm.h differs from what cbindgen generates from capi/src now ({}); \
             regenerate it with `MCM_UPDATE_HEADER=1 cargo test -p mcm-capi --test header` and \
             commit it",
            difference(&checked_in, &generated)
        );
    }
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
