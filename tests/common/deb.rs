//! The Debian package as the tests make it: cargo-deb around the `mcm` cargo built for this
//! test run (`--no-build`: no release build), for `tests/end_to_end/deb_package.rs` and
//! `tests/vm/package.rs`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn cargo() -> Command {
    Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()))
}

/// `Err` naming the missing tool when cargo-deb is not installed.
pub fn cargo_deb_installed() -> Result<(), String> {
    let ok = cargo()
        .args(["deb", "--version"])
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        Ok(())
    } else {
        Err("cargo-deb is not installed (cargo install cargo-deb --locked)".into())
    }
}

/// Make the packages `(file name, version)` in `dir` (emptied first) from this test run's `mcm`;
/// a version of `None` is the manifest's. Their paths, in order; panics with cargo-deb's output
/// when it fails.
pub fn build(dir: &Path, packages: &[(&str, Option<&str>)]) -> Vec<PathBuf> {
    super::machine::share();
    let target = dir.join("target");
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(target.join("release")).unwrap();
    std::fs::copy(env!("CARGO_BIN_EXE_mcm"), target.join("release/mcm")).unwrap();
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml");
    packages
        .iter()
        .map(|(name, version)| {
            let deb = dir.join(name);
            let mut cmd = cargo();
            cmd.args([
                "deb",
                "--no-build",
                "--fast",
                "--no-strip",
                "--manifest-path",
            ])
            .arg(&manifest)
            .arg("--output")
            .arg(&deb)
            .env("CARGO_TARGET_DIR", &target);
            if let Some(v) = version {
                cmd.args(["--deb-version", v]);
            }
            run(&mut cmd);
            deb
        })
        .collect()
}

/// Run `cmd`, panicking with its output unless it succeeds.
pub fn run(cmd: &mut Command) -> Output {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    assert!(
        out.status.success(),
        "{cmd:?}: {}\nstdout: {}\nstderr: {}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}
