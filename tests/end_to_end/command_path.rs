//! End to end, the gateway's side of the command path: `status` answered from the newest state
//! without waiting for a cycle, `hold` going out ahead of a flood of `pvt_points` batches, and
//! every reply delivered across a gateway stall (SIGSTOP).
//!
//! Times are the robot's (`axis_states.time` of status results). Every wait is bounded; the
//! one fixed pause is the stall itself (the gateway stopped for 1 s), not a synchronisation.

use crate::common;

use common::{Client, Mcm, WAIT, assert_ok, assert_status, config_file, is_error, time_of};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// One control cycle of the P-Rob2 [s].
const CYCLE: f64 = 0.005;

/// Wait (bounded) until `cond` holds, polling at a gentle pace.
fn wait_until(what: &str, cond: impl Fn() -> bool) {
    let deadline = Instant::now() + WAIT;
    while !cond() {
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn status_is_answered_from_the_newest_state_without_waiting_for_a_cycle() {
    let mcm = Mcm::start("cp-status");
    let mut c = mcm.client();
    c.wait_drives_online();
    const N: usize = 200;
    let mut batch = String::new();
    for k in 0..N {
        batch.push_str(if k % 2 == 0 {
            "{\"command\":\"status\"}\n"
        } else {
            "{\"command\":\"status\",\"arguments\":{\"detail\":true}}\n"
        });
    }
    c.send_raw(batch.as_bytes());
    let times: Vec<f64> = (0..N)
        .map(|_| {
            let s = c.recv();
            assert_status(&s, "OFF");
            time_of(&s)
        })
        .collect();
    let repeats = times.windows(2).filter(|w| w[0] == w[1]).count();
    let span = times[N - 1] - times[0];
    // Through the core, every result would be one cycle later than the one before.
    assert!(
        repeats > 0 && span < (N as f64 - 1.0) * CYCLE,
        "{N} statuses over {span} s of robot time, {repeats} repeated times: {times:?}"
    );
}

#[test]
fn a_status_right_after_a_result_is_never_older_than_that_result() {
    let mcm = Mcm::start("cp-order");
    let mut c = mcm.client();
    c.wait_drives_online();
    // `hold` is answered with the state of the cycle that executed it; the status sent at once
    // after it comes from the gateway's newest state, which must be that cycle or a later one.
    for k in 0..200 {
        let held = c.request(r#"{"command":"hold"}"#);
        assert_status(&held, "HOLD");
        let s = c.request(r#"{"command":"status"}"#);
        assert_status(&s, "HOLD");
        assert!(
            time_of(&s) >= time_of(&held),
            "round {k}: status at {} is older than the hold it follows at {}",
            time_of(&s),
            time_of(&held)
        );
    }
}

/// A 1000-point batch the gateway cannot refuse (every point is reachable and within its speed
/// limit) but the core does (the jumps between points break the acceleration limit).
fn refused_batch() -> String {
    let points: Vec<String> = (0..1000)
        .map(|k| {
            let q = if k % 2 == 0 { 0 } else { 5 };
            format!("{{\"position\":[{q},0,0,0,0,0],\"velocity\":[0,0,0,0,0,0]}}")
        })
        .collect();
    format!(
        "{{\"command\":\"pvt_points\",\"arguments\":{{\"points\":[{}]}}}}\n",
        points.join(",")
    )
}

#[test]
fn hold_goes_out_ahead_of_a_flood_of_pvt_points() {
    // All flooders connect from 127.0.0.1: the per-address cap is lifted to the port's
    // capacity, as if they came from many machines.
    let config = config_file("cp-flood", |base| {
        format!("{base}\n[gateway.connections]\nmax_per_peer = 64\n")
    });
    let mcm = Mcm::start_with("cp-flood", &["--config", config.path()]);
    let mut c = mcm.client();
    c.wait_drives_online();
    assert_ok(&c.request(r#"{"command":"calibrate"}"#));
    assert_status(
        &c.request(r#"{"command":"pvt","arguments":{"dt":0.01}}"#),
        "PVT",
    );

    const FLOODERS: usize = 24;
    let stop = Arc::new(AtomicBool::new(false));
    let refused_by_core = Arc::new(AtomicUsize::new(0));
    let batch = Arc::new(refused_batch());
    let flooders: Vec<_> = (0..FLOODERS)
        .map(|_| {
            let (stop, refused, batch) = (stop.clone(), refused_by_core.clone(), batch.clone());
            let mut f = Client::connect(mcm.json);
            std::thread::spawn(move || {
                while !stop.load(Ordering::Relaxed) {
                    f.send_raw(batch.as_bytes());
                    let r = f.recv();
                    assert!(is_error(&r), "the batch is refused: {r}");
                    let text = r["error_message"].to_string();
                    if text.contains("pvt_points refused") {
                        refused.fetch_add(1, Ordering::Relaxed);
                    }
                }
            })
        })
        .collect();
    // The flood reaches the core: it refuses whole batches for their accelerations.
    wait_until("the core refusing flooded batches", || {
        refused_by_core.load(Ordering::Relaxed) >= FLOODERS
    });

    let before = c.request(r#"{"command":"status"}"#);
    assert_status(&before, "PVT");
    let held = c.request(r#"{"command":"hold"}"#);
    assert_status(&held, "HOLD");
    let cycles = (time_of(&held) - time_of(&before)) / CYCLE;
    stop.store(true, Ordering::Relaxed);
    for f in flooders {
        f.join().expect("flooder");
    }
    assert!(
        cycles <= 10.0,
        "hold took {cycles} cycles of robot time behind {FLOODERS} flooding connections"
    );
}

#[test]
fn every_reply_arrives_across_a_one_second_gateway_stall() {
    let mcm = Mcm::start("cp-stall");
    let mut c = mcm.client();
    c.wait_drives_online();

    const CLIENTS: usize = 8;
    /// Requests each client keeps under way at once.
    const PIPELINE: usize = 4;
    let stop = Arc::new(AtomicBool::new(false));
    let counts: Arc<Vec<AtomicUsize>> =
        Arc::new((0..CLIENTS).map(|_| AtomicUsize::new(0)).collect());
    let workers: Vec<_> = (0..CLIENTS)
        .map(|i| {
            let (stop, counts) = (stop.clone(), counts.clone());
            let mut w = Client::connect(mcm.json);
            std::thread::spawn(move || {
                let mut errors = Vec::new();
                let lines = "{\"command\":\"info\"}\n".repeat(PIPELINE);
                while !stop.load(Ordering::Relaxed) {
                    w.send_raw(lines.as_bytes());
                    for _ in 0..PIPELINE {
                        let r = w.recv();
                        if is_error(&r) || r["result_type"] != "initialization" {
                            errors.push(r);
                        }
                        counts[i].fetch_add(1, Ordering::Relaxed);
                    }
                }
                errors
            })
        })
        .collect();
    let all_above = |n: usize| counts.iter().all(|c| c.load(Ordering::Relaxed) >= n);
    wait_until("every client busy", || all_above(20));

    let pid = mcm.gateway_pid;
    // SAFETY: kill(2) with a pid of a child process this test started; no memory involved.
    assert_eq!(unsafe { libc::kill(pid, libc::SIGSTOP) }, 0);
    let stopped_at: Vec<usize> = counts.iter().map(|c| c.load(Ordering::Relaxed)).collect();
    std::thread::sleep(Duration::from_secs(1)); // the stall itself
    // SAFETY: as above.
    assert_eq!(unsafe { libc::kill(pid, libc::SIGCONT) }, 0);

    let low = stopped_at.iter().max().copied().unwrap_or(0) + 4 * PIPELINE;
    wait_until("every client busy again after the stall", || all_above(low));
    stop.store(true, Ordering::Relaxed);
    for w in workers {
        let errors = w.join().expect("client thread");
        assert!(errors.is_empty(), "results lost or wrong: {errors:?}");
    }
    let s = c.request(r#"{"command":"status"}"#);
    assert_status(&s, "OFF");
}
