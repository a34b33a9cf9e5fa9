//! The Python package's ctypes structures (`python/src/mcm/layout.py`) against the Rust
//! layouts of the shared-memory samples: sizes, alignments, field offsets, iceoryx2 type names
//! (with their layout versions), constants, reply locations, the words of every refusal reason,
//! and the samples `python/src/mcm/wire.py` encodes commands of every kind into. The truth is what
//! `cargo run -p mcm-shared --example layout` prints; this test includes that example, writes
//! its JSON to a file and runs `python/tests/test_layout.py` with the system's `python3`
//! (standard library only, no virtual environment needed).

use crate::common;

#[path = "../../shared/examples/layout.rs"]
mod layout;

use common::python;

#[test]
fn python_ctypes_structures_match_the_rust_layouts() {
    common::machine::share();
    let Some(py) =
        python::system_python().map_or_else(|e| python::missing("python_layout", &e), Some)
    else {
        return;
    };
    let json = std::env::temp_dir().join(format!("mcm-layout-{}.json", std::process::id()));
    std::fs::write(&json, layout::layout_json()).unwrap();
    let src = python::repo_root().join("python/src");
    let log = python::unittest(
        &py,
        &["tests.test_layout"],
        &[
            ("PYTHONPATH", src.as_os_str()),
            ("MCM_LAYOUT_JSON", json.as_os_str()),
        ],
    );
    let _ = std::fs::remove_file(&json);
    let log = log.unwrap_or_else(|e| panic!("the Python layout check failed:\n{e}"));
    python::assert_all_passed(&log, python::tests_defined(&["test_layout"]));
}
