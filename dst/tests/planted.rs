//! A planted bug is caught within the CI budget and shrunk: the stop after a safety trip
//! braking at a tenth of the maximum deceleration (`PlantedBug::QuickStopSoft`, compiled in
//! with rt-core's feature `planted-bugs`). The seeds, run in order within a budget, must
//! break an invariant a soft stop breaks (an axis travels beyond its braking distance after a
//! trip, or passes a limit braking), the shrinking must leave a short script that still breaks
//! it, and the same script without the bug must pass: the failure is the bug's, not the
//! script's. Figures in `docs/testing.md`, "Deterministic
//! simulation testing".

use mcm_dst::run::{PlantedBug, RunOptions, run};
use mcm_dst::script::{Script, replay};
use mcm_dst::shrink::{LATER_CYCLES, invariant_of, shrink};
use mcm_shared::alloc_count::CountingAlloc;

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

/// The invariants a stop that brakes too softly breaks: the travel after a trip, or a limit
/// passed while it brakes.
const BROKEN_BY_A_SOFT_STOP: [&str; 3] = [
    "travelled since the trip",
    "its stop should have ended",
    "beyond the software limits",
];

#[test]
fn a_soft_stop_after_a_trip_is_caught_and_shrunk() {
    // Seeds in order, as a one-job campaign runs them, within a budget of simulated time; a
    // run that breaks an invariant also without the bug is a finding of its own
    // (`docs/findings.md`), not the bug caught: it is passed over.
    let budget_s = 3600.0;
    let mut spent_s = 0.0;
    let mut passed_over = Vec::new();
    let (caught, v) = (0..)
        .map_while(|seed| {
            (spent_s < budget_s).then(|| {
                let mut o = RunOptions::new(seed, 60.0);
                o.planted = Some(PlantedBug::QuickStopSoft);
                let r = run(&o);
                spent_s += r.simulated_s;
                r
            })
        })
        .find_map(|r| {
            let v = r.violation.clone().filter(|v| !v.quiet_phase)?;
            let alone = run(&RunOptions::new(r.seed, 60.0)).violation;
            if alone.is_some_and(|a| !a.quiet_phase) {
                passed_over.push(r.seed);
                return None;
            }
            Some((r, v))
        })
        .unwrap_or_else(|| {
            panic!("the planted bug was not caught within {budget_s} simulated s (seeds passed over as findings of their own: {passed_over:?})")
        });
    eprintln!(
        "caught: seed {} after {spent_s:.0} simulated s (passed over: {passed_over:?}): {v}",
        caught.seed
    );
    assert!(
        BROKEN_BY_A_SOFT_STOP.contains(&invariant_of(&v.message)),
        "the invariant the bug breaks: {v}"
    );

    let s = shrink(&caught.script, &v, 250).expect("the run's own script reproduces it");
    eprintln!(
        "shrunk with {} replays: {} inputs of {}, failing at cycle {}: {}\n{}",
        s.replays,
        s.script.events.len(),
        s.inputs_before,
        s.violation.cycle,
        s.violation.message,
        s.script
    );
    assert!(
        s.script.events.len() * 10 <= s.inputs_before,
        "shrunk to at most a tenth: {} of {}",
        s.script.events.len(),
        s.inputs_before
    );
    // The text form reads back, and the shrunk script fails with the bug and passes without.
    let text = s.script.to_string();
    let back: Script = text.parse().expect("the script's text reads back");
    let horizon = s.violation.cycle + LATER_CYCLES;
    let again = replay(&back, horizon).expect("the shrunk script fails again");
    assert_eq!(invariant_of(&again.message), invariant_of(&v.message));
    let without = Script {
        planted: None,
        ..back
    };
    assert_eq!(replay(&without, horizon), None, "without the bug it passes");
}
