//! The build that `cargo test --workspace` (CI's test command) does not otherwise compile,
//! checked (no code generation) with the cargo of the test run, in the workspace's target
//! directory; a failed check fails the test with cargo's output, and the time it took is
//! printed: the real-time core without the simulator (`--no-default-features`: real drives
//! only), its unit tests included. The `sim` feature is always on in the workspace, so the code
//! under `#[cfg(not(feature = "sim"))]` would never be compiled. (The fuzz target's library,
//! `fuzz/`, is a member of the workspace: the test run compiles and runs it.)

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The longest a check may take: a check from a cold target directory on a slow machine.
const CHECK_BOUND: Duration = Duration::from_secs(20 * 60);

/// `cargo check` of `args` (after `check`) in the workspace; panics with cargo's output when it
/// fails or does not finish within [`CHECK_BOUND`].
fn cargo_check(args: &[&str]) {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut cmd = Command::new(env!("CARGO"));
    cmd.current_dir(workspace)
        .arg("check")
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let what = format!("cargo check {}", args.join(" "));
    let started = Instant::now();
    let mut child = cmd
        .spawn()
        .unwrap_or_else(|e| panic!("{what}: cannot run cargo: {e}"));
    let read = |mut from: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut text = String::new();
            let _ = from.read_to_string(&mut text);
            text
        })
    };
    let stdout = read(Box::new(child.stdout.take().unwrap()));
    let stderr = read(Box::new(child.stderr.take().unwrap()));
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for cargo") {
            break Some(status);
        }
        if started.elapsed() > CHECK_BOUND {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let output = format!(
        "{}{}",
        stdout.join().unwrap_or_default(),
        stderr.join().unwrap_or_default()
    );
    match status {
        Some(s) if s.success() => {}
        Some(s) => panic!("{what} failed ({s}):\n{output}"),
        None => panic!("{what} did not finish within {CHECK_BOUND:?}:\n{output}"),
    }
    eprintln!("{what}: {:.1} s", started.elapsed().as_secs_f64());
}

#[test]
fn the_core_compiles_without_the_simulator() {
    cargo_check(&[
        "-p",
        "mcm-rt-core",
        "--no-default-features",
        "--lib",
        "--tests",
    ]);
}
