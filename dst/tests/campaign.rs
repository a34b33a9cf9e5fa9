//! The CI budget of the deterministic simulation: replay bit for bit, and a small campaign in
//! which no invariant may break and every run's quiet phase must end in a usable calibrated
//! HOLD (one job: the same seeds every time). Debug build (the workspace's dev profile); the
//! figures are in `docs/testing.md`, "Deterministic simulation testing".

use mcm_dst::campaign::{CampaignOptions, campaign_with};
use mcm_dst::hash::first_divergence;
use mcm_dst::run::{RunOptions, run};
use mcm_shared::alloc_count::CountingAlloc;
use std::sync::Mutex;

// The allocation invariant needs the counting allocator to see anything.
#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

#[test]
fn a_seed_replays_bit_for_bit_and_another_seed_differs() {
    let a = run(&RunOptions::new(5, 10.0));
    let b = run(&RunOptions::new(5, 10.0));
    let c = run(&RunOptions::new(6, 10.0));
    assert!(a.cycles > 2_000, "the run ran: {} cycles", a.cycles);
    assert_eq!((a.hash, a.cycles), (b.hash, b.cycles), "seed 5 twice");
    assert_eq!(first_divergence(&a.checkpoints, &b.checkpoints), None);
    assert_eq!(
        a.checkpoints.len() as u64,
        a.cycles,
        "a checkpoint per cycle"
    );
    assert_eq!(a.violation, b.violation);
    assert_ne!(a.hash, c.hash, "the hash sees a different run");
    assert!(first_divergence(&a.checkpoints, &c.checkpoints).is_some());
}

#[test]
fn the_allocation_check_sees_an_allocation() {
    // Guards the "no allocation in the cycle" invariant against a counter that sees nothing.
    let ((), counts) = mcm_shared::alloc_count::count(|| {
        drop(std::hint::black_box(vec![0u8; 8]));
    });
    assert_eq!(counts.allocations, 1);
}

#[test]
fn a_small_campaign_breaks_no_invariant_and_every_run_recovers() {
    // (seed, runs so far, simulated s so far) as the observer saw each run.
    let seen = Mutex::new(Vec::new());
    let options = CampaignOptions {
        first_seed: 1_000,
        budget_s: 600.0,
        run_s: 20.0,
        jobs: 1,
        planted: None,
        keep_going: false,
    };
    let r = campaign_with(&options, |run, at| {
        seen.lock()
            .unwrap()
            .push((run.seed, at.runs, at.simulated_s));
    });
    eprintln!("{}", r.summary());
    let seen = seen.into_inner().unwrap();
    let expected: Vec<(u64, u64)> = (0..r.runs).map(|k| (1_000 + k, k + 1)).collect();
    let got: Vec<(u64, u64)> = seen.iter().map(|&(seed, runs, _)| (seed, runs)).collect();
    assert_eq!(
        got, expected,
        "the observer sees every run, in order with one job"
    );
    assert_eq!(
        seen.last().map(|s| s.2),
        Some(r.simulated_s),
        "the last progress is the report's"
    );
    for f in &r.failures {
        let v = f.violation.as_ref().expect("a failure");
        eprintln!("seed {}: {v}", f.seed);
    }
    let broken: Vec<String> = r
        .failures
        .iter()
        .filter_map(|f| {
            f.violation
                .as_ref()
                .map(|v| format!("seed {}: {v}", f.seed))
        })
        .collect();
    assert!(
        broken.is_empty(),
        "invariants broken or quiet phases that did not end in a usable calibrated HOLD (replay with mcm-dst --seed N --seconds 20):\n{}",
        broken.join("\n")
    );
    assert!(
        r.runs >= 2 && r.simulated_s >= 600.0,
        "{} runs, {} simulated s",
        r.runs,
        r.simulated_s
    );
    assert!(
        r.answers[0] > 100 && r.answers[1] > 10,
        "commands answered: {:?}",
        r.answers
    );
    assert!(r.modes_reached[mcm_shared::mode::Mode::Calibration as usize] > 0);
}
