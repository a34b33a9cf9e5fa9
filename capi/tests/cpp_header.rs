//! `include/mcm/mcm.hpp` compiles with every method of its one command set instantiated for both
//! handles (`tests/cpp/methods.cpp`), with and without exceptions, warnings as errors. The examples
//! (`tests/end_to_end/examples_cpp.rs` of the workspace) use only some methods; a template member
//! no example calls is checked here. Needs a C++17 compiler (`c++`); without one the test says it
//! is skipped, except when `CI` is set, where it fails.

mod common;

use std::path::Path;
use std::process::Command;

#[test]
fn every_method_compiles_for_both_handles() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    for flags in [&[][..], &["-fno-exceptions"][..]] {
        let out = match Command::new("c++")
            .args([
                "-std=c++17",
                "-Wall",
                "-Wextra",
                "-Werror",
                "-pedantic",
                "-fsyntax-only",
            ])
            .args(flags)
            .arg("-I")
            .arg(dir.join("include"))
            .arg(dir.join("tests/cpp/methods.cpp"))
            .output()
        {
            Ok(out) => out,
            Err(e) => {
                common::skip(
                    "every_method_compiles_for_both_handles",
                    &format!(
                        "no C++ compiler `c++` ({e}; install with `apt-get install g++`; .ci/run \
                         does so on CI)"
                    ),
                );
                return;
            }
        };
        assert!(
            out.status.success(),
            "mcm.hpp does not compile ({flags:?}):\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
