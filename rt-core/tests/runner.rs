//! `runner::run` in this process: the set-up errors it names (no CAN interface, an unwritable
//! candump log, no real-time scheduling when not allowed) and a short run of the simulated
//! robot that stops when asked, as on SIGTERM. Only the last test touches the process-wide stop
//! flag; each test uses its own instance name.

mod common;

use common::{NO_CPU, options};
use mcm_rt_core::runner::{self, RunError, RunOptions};
use mcm_shared::config::BusBackend;
use mcm_shared::sample::StateSample;
use mcm_shared::service::{STATE_KEY, ServiceNames};
use std::path::PathBuf;
use std::time::Duration;

fn never_started(report: &mcm_rt_core::realtime::RtReport) {
    panic!("started despite a set-up error: {report}");
}

#[test]
fn a_missing_can_interface_is_named() {
    for candump in [
        None,
        Some(std::env::temp_dir().join("rtcov-never-written.log")),
    ] {
        let mut opts = options("no-can");
        opts.config.bus.backend = BusBackend::Socketcan;
        opts.config.bus.interface = "mcmnocan9".into();
        opts.candump = candump;
        let err = runner::run(opts, never_started).unwrap_err();
        assert!(matches!(err, RunError::Bus(_)), "{err:?}");
        let text = err.to_string();
        assert!(
            text.starts_with("cannot open the CAN bus") && text.contains("mcmnocan9"),
            "{text}"
        );
    }
}

#[test]
fn an_unwritable_candump_log_is_named_with_its_path() {
    let mut opts = options("bad-candump");
    let path = PathBuf::from("/nonexistent-mcm-dir/frames.log");
    opts.candump = Some(path.clone());
    let err = runner::run(opts, never_started).unwrap_err();
    let RunError::Candump { path: named, .. } = &err else {
        panic!("a candump error: {err:?}")
    };
    assert_eq!(named, &path.display().to_string());
    assert!(
        err.to_string().contains("/nonexistent-mcm-dir/frames.log"),
        "{err}"
    );
}

#[test]
fn without_real_time_scheduling_it_refuses_unless_allowed() {
    let mut opts = options("not-rt");
    opts.allow_non_realtime = false;
    let err = runner::run(opts, never_started).unwrap_err();
    let RunError::NotRealtime { report } = &err else {
        panic!("not real-time: {err:?}")
    };
    let pinned = report.pinned_cpu.as_ref().unwrap_err();
    assert!(
        pinned.contains(&format!("CPU {NO_CPU} is not available")),
        "{pinned}"
    );
    assert!(err.to_string().contains("--allow-non-realtime"), "{err}");
}

/// Wait (at most `limit`) until the state blackboard of `instance` shows cycle `cycles`; the
/// cycle seen.
fn wait_for_cycles(instance: &str, cycles: u64, limit: Duration) -> u64 {
    let names = ServiceNames::new(instance).unwrap();
    let node = common::node();
    // mcm-rt created the state service before on_started.
    let reader = common::state_reader(&node, &names);
    let entry = reader.entry::<StateSample>(&STATE_KEY).unwrap();
    let deadline = std::time::Instant::now() + limit;
    loop {
        let seq = entry.get().seq;
        if seq >= cycles {
            return seq;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "only {seq} cycles published within {limit:?}"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn a_simulated_run_logs_its_frames_stops_when_asked_and_saves_the_robot() {
    let opts = options("sim-run");
    let instance = opts.names.instance().to_string();
    let log = std::env::temp_dir().join(format!("mcm-rtcov-{instance}.log"));
    let state = mcm_sim::snapshot::state_path(&instance);
    let _ = std::fs::remove_file(&state);
    let opts = RunOptions {
        candump: Some(log.clone()),
        ..opts
    };
    let (tx, rx) = std::sync::mpsc::channel();
    let run = std::thread::spawn(move || {
        runner::run(opts, move |report| tx.send(report.is_realtime()).unwrap())
    });
    let realtime = rx
        .recv_timeout(Duration::from_secs(20))
        .expect("the cycle starts");
    assert!(!realtime, "no machine has CPU {NO_CPU}");
    let published = wait_for_cycles(&instance, 5, Duration::from_secs(20));
    mcm_rt_core::signals::request_stop();
    let summary = run.join().unwrap().expect("a clean stop");
    assert!(!summary.realtime.is_realtime());
    assert!(
        summary.figures.cycles >= published,
        "{} cycles run, {published} seen published",
        summary.figures.cycles
    );
    assert!(summary.figures.latency_max_ns >= summary.figures.latency_p99_ns);
    let frames = std::fs::read_to_string(&log).unwrap();
    assert!(
        frames.lines().any(|l| l.contains("sim0")),
        "candump lines name the bus: {frames:.200}"
    );
    assert!(
        state.exists(),
        "the simulated robot is saved for the next run"
    );
    std::fs::remove_file(&log).unwrap();
    std::fs::remove_file(&state).unwrap();
}
