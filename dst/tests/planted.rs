//! A planted bug is caught within the CI budget and shrunk: the stop after a safety trip
//! braking at a tenth of the maximum deceleration (`PlantedBug::QuickStopSoft`, compiled in
//! with rt-core's feature `planted-bugs`). The campaign must break the standstill invariant
//! (an axis travels beyond its braking distance after a trip), the shrinking must leave a
//! short script that still breaks it, and the same script without the bug must pass: the
//! failure is the bug's, not the script's. Figures in `docs/testing.md`, "Deterministic
//! simulation testing".

use mcm_dst::campaign::{CampaignOptions, campaign};
use mcm_dst::run::PlantedBug;
use mcm_dst::script::{Script, replay};
use mcm_dst::shrink::{LATER_CYCLES, invariant_of, shrink};
use mcm_shared::alloc_count::CountingAlloc;

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

#[test]
fn a_soft_stop_after_a_trip_is_caught_and_shrunk() {
    let r = campaign(&CampaignOptions {
        first_seed: 0,
        budget_s: 3600.0,
        run_s: 60.0,
        jobs: 1,
        planted: Some(PlantedBug::QuickStopSoft),
    });
    eprintln!("{}", r.summary());
    let caught = r
        .failures
        .iter()
        .find(|f| f.violation.as_ref().is_some_and(|v| !v.quiet_phase))
        .unwrap_or_else(|| {
            panic!(
                "the planted bug was not caught in {} runs ({:.0} simulated s)",
                r.runs, r.simulated_s
            )
        });
    let v = caught.violation.clone().expect("a violation");
    eprintln!("caught: seed {}: {v}", caught.seed);
    assert_eq!(
        invariant_of(&v.message),
        "travelled since the trip",
        "the invariant the bug breaks: {v}"
    );

    let s = shrink(&caught.script, &v, 80).expect("the run's own script reproduces it");
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
    assert_eq!(invariant_of(&again.message), "travelled since the trip");
    let without = Script {
        planted: None,
        ..back
    };
    assert_eq!(replay(&without, horizon), None, "without the bug it passes");
}
