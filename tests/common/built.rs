//! The executables `cargo test --workspace` (the test command) built, found by cargo's own account
//! of them, for the tests that run one that is not their package's binary: a test executable run in
//! the guest (`vm.rs`), the client's examples (`tests/end_to_end/examples_rust.rs`), the launcher
//! `mcm` for the client's own tests (`client/tests/live.rs` includes this file).
//!
//! Asking cargo for the one target alone (`-p`, `--test`, `--bins`) would unify the features
//! of its dependencies differently from the whole workspace: cargo would build another copy of
//! it and of what it depends on (a minute or more in CI, each), and the copy can overwrite the
//! binaries the other tests run (`target/debug/mcm`). So this asks for what the test command
//! builds, `cargo test --workspace --no-run`: within that command everything is built already
//! and it takes seconds; a test run alone builds the whole workspace's tests once.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;

/// The workspace's target directory (the parent of `CARGO_TARGET_TMPDIR`).
pub fn target_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("CARGO_TARGET_TMPDIR is target/tmp")
        .to_path_buf()
}

/// The profile directory of this test's build (`target/debug`, `target/release`).
fn profile_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test's path");
    // target/<profile>/deps/<test>-<hash>
    exe.parent()
        .and_then(Path::parent)
        .expect("target/<profile>")
        .to_path_buf()
}

/// Cargo's artifact messages (`--message-format=json`) of every executable of
/// `cargo test --workspace --no-run` (with this test's profile, the cargo of this test run, in
/// this workspace and target directory), asked once per test process. Panics with cargo's
/// output when the build fails.
fn executables() -> &'static [Value] {
    static EXECUTABLES: OnceLock<Vec<Value>> = OnceLock::new();
    EXECUTABLES.get_or_init(|| {
        let mut cargo = Command::new(env!("CARGO"));
        cargo.args(["test", "--workspace", "--no-run", "--message-format=json"]);
        if profile_dir().file_name().is_some_and(|n| n == "release") {
            cargo.arg("--release");
        }
        let out = cargo
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .env("CARGO_TARGET_DIR", target_dir())
            .stdin(Stdio::null())
            .output()
            .expect("run cargo");
        assert!(
            out.status.success(),
            "cargo test --workspace --no-run failed ({}):\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .filter_map(|l| serde_json::from_str::<Value>(l).ok())
            .filter(|v| v["reason"] == "compiler-artifact" && v["executable"].is_string())
            .collect()
    })
}

/// Which executable: its target's `name` and `kind` (`bin`, `lib`, `test`), whether it is the
/// test harness's build of it (`test`), and the package whose manifest is `manifest`
/// (relative to the manifest of the package this test belongs to: `Cargo.toml`,
/// `client/Cargo.toml`, `../Cargo.toml`).
pub struct Executable<'a> {
    pub name: &'a str,
    pub kind: &'a str,
    pub test: bool,
    pub manifest: &'a str,
}

impl Executable<'_> {
    fn is(&self, artifact: &Value) -> bool {
        let canonical = |p: &Path| p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
        let manifest = canonical(&Path::new(env!("CARGO_MANIFEST_DIR")).join(self.manifest));
        artifact["target"]["name"] == self.name
            && artifact["target"]["kind"]
                .as_array()
                .is_some_and(|k| k.iter().any(|k| k == self.kind))
            && artifact["profile"]["test"] == self.test
            && artifact["manifest_path"]
                .as_str()
                .is_some_and(|m| canonical(Path::new(m)) == manifest)
    }

    /// Its path, as the test command built it; panics when cargo named none such.
    pub fn path(&self) -> PathBuf {
        executables()
            .iter()
            .find(|v| self.is(v))
            .and_then(|v| v["executable"].as_str().map(PathBuf::from))
            .unwrap_or_else(|| {
                panic!(
                    "cargo test --workspace named no executable of the {} target {} of {} \
                     (test harness: {})",
                    self.kind, self.name, self.manifest, self.test
                )
            })
    }
}
