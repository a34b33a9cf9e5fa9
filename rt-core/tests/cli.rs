//! The `mcm-rt` binary as a user runs it: errors in its arguments are named on stderr with a
//! failing exit status; a simulated run prints its ready line, stops on SIGTERM and sums up.

mod common;

use common::{mcm_rt, start, stop};

/// Run `mcm-rt args`; its exit code and stderr.
fn run(args: &[&str]) -> (Option<i32>, String) {
    let out = mcm_rt().args(args).output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_missing_config_file_is_named() {
    let (code, err) = run(&["--config", "/nonexistent/robot.toml"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.starts_with("mcm-rt: ") && err.contains("/nonexistent/robot.toml"),
        "{err}"
    );
}

#[test]
fn an_invalid_instance_name_is_named() {
    let (code, err) = run(&["--instance", "no spaces!"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.starts_with("mcm-rt: ") && err.contains("no spaces!"),
        "{err}"
    );
}

#[test]
fn an_unknown_argument_is_a_usage_error() {
    let (code, err) = run(&["--frobnicate"]);
    assert_eq!(code, Some(2), "clap's usage error: {err}");
    assert!(err.contains("--frobnicate"), "{err}");
}

#[test]
fn a_simulated_run_says_ready_and_stops_on_sigterm() {
    let instance = format!("cli-run-{}", std::process::id());
    let (child, ready) = start(mcm_rt().args(["--instance", &instance, "--allow-non-realtime"]));
    assert_eq!(
        ready.trim_end(),
        format!("mcm-rt ready instance={instance} bus=sim")
    );
    // The handlers are installed before the ready line: SIGTERM now stops the loop cleanly.
    let (status, err) = stop(child);
    assert!(status.success(), "{status}: {err}");
    assert!(err.contains("mcm-rt: stopped after "), "{err}");
    let _ = std::fs::remove_file(mcm_sim::snapshot::state_path(&instance));
}
