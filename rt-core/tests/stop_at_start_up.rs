//! A stop asked for while the core starts up (systemd's SIGTERM while the bus and the services
//! open, before the first cycle) is not lost: the run ends in the controlled stop instead of
//! running on until SIGKILL. A process of its own: it uses the process-wide stop flag.

mod common;

use common::options;
use mcm_rt_core::runner;
use std::time::Duration;

#[test]
fn a_stop_asked_for_before_the_first_cycle_ends_the_run() {
    let opts = options("stop-at-start-up");
    let state = mcm_sim::snapshot::state_path(opts.names.instance());
    let (tx, rx) = std::sync::mpsc::channel();
    // `on_started` runs on the cycle thread after the set-up and before the first cycle: the
    // last moment of the start-up.
    std::thread::spawn(move || {
        let result = runner::run(opts, |_| mcm_rt_core::signals::request_stop());
        let _ = tx.send(result);
    });
    let summary = rx
        .recv_timeout(Duration::from_secs(30))
        .expect("the run ended after a stop asked for at start-up")
        .expect("a clean stop");
    assert!(
        summary.figures.cycles > 0,
        "the loop ran the controlled stop"
    );
    let _ = std::fs::remove_file(state);
}
