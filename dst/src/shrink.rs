//! Shrinking a failing run to the inputs its failure needs: every input of one sender at a
//! time first, then delta debugging (Zeller's `ddmin`) over the run's script
//! ([`crate::script`]). A candidate keeps a subset of the
//! inputs, in order, over the same seed's world; it "still fails" when its replay breaks the
//! same invariant ([`invariant_of`]) by the failing cycle (plus [`LATER_CYCLES`]). The result
//! is 1-minimal when the replay budget allows: removing any one input left makes the failure
//! go away.
//!
//! Nothing here runs inside the cycle.

use crate::invariants::Violation;
use crate::script::{Input, Script, replay};

/// A candidate may fail this many cycles after the original failure and still count [cycles]
/// (1 s at 200 Hz): an input removed may delay what it did not cause.
pub const LATER_CYCLES: u64 = 200;

/// The invariant a violation's message is about (the words that name it), so that a shrunk
/// run is held to the same failure, not any failure.
pub fn invariant_of(message: &str) -> &'static str {
    const INVARIANTS: [&str; 21] = [
        // A refusal that says what was not so (first: the reason it quotes may contain the
        // words of another invariant, "flagged calibrated", "beyond the software limits").
        "refused as not allowed in",
        "refused as axis",
        "refused for the emergency stop",
        "but the mode went from",
        "beyond the mechanical stops",
        "beyond the software limits",
        // Before "flagged calibrated": an OK to `calibrate` with an axis not flagged says both.
        "of unknown kind",
        "answered OK",
        "flagged calibrated",
        "travelled since the trip",
        "cartesian_state",
        "its stop should have ended",
        "allocated",
        "CPU time",
        "not finite",
        "unknown mode",
        "illegal mode transition",
        "not answered by cycle",
        "never asked",
        "answered as kind",
        "does not decode",
    ];
    INVARIANTS
        .iter()
        .find(|words| message.contains(*words))
        .copied()
        .unwrap_or("another invariant")
}

/// A shrunk run.
#[derive(Debug, Clone)]
pub struct Shrunk {
    pub script: Script,
    /// The violation of the shrunk script's replay.
    pub violation: Violation,
    /// Inputs before the shrinking (those up to the failing cycle).
    pub inputs_before: usize,
    /// Replays made.
    pub replays: u32,
    /// Whether the budget ran out before the result was 1-minimal.
    pub budget_spent: bool,
}

/// Shrink `script`, whose replay broke `failure`, with at most `max_replays` replays. `None`
/// when the script's own replay does not break the same invariant (a run that is not
/// reproducible from its script: a bug of the tester, said so by the caller).
pub fn shrink(script: &Script, failure: &Violation, max_replays: u32) -> Option<Shrunk> {
    let target = invariant_of(&failure.message);
    let horizon = failure.cycle + LATER_CYCLES;
    let replays = std::cell::Cell::new(0u32);
    let fails = |events: &[crate::script::Event]| -> Option<Violation> {
        replays.set(replays.get() + 1);
        let candidate = Script {
            seed: script.seed,
            fault_kinds: script.fault_kinds,
            planted: script.planted,
            events: events.to_vec(),
        };
        replay(&candidate, horizon).filter(|v| invariant_of(&v.message) == target)
    };
    // A violation of cycle k is of the k-th step, which inputs before cycle k reached; later
    // ones cannot have caused it.
    let mut events: Vec<_> = script
        .events
        .iter()
        .copied()
        .filter(|e| e.cycle < failure.cycle)
        .collect();
    let inputs_before = events.len();
    let mut violation = fails(&events)?;
    // First every input of one sender at a time (a client, the driver, the fault injector,
    // the bus faults as one): most senders have nothing to do with a failure, and each goes
    // in one replay instead of the many ddmin takes to find its scattered inputs.
    let mut senders: Vec<Option<u64>> = Vec::new();
    for e in &events {
        let sender = match e.input {
            Input::Command(c) => Some(c.client_id),
            Input::Bus(_) => None,
        };
        if !senders.contains(&sender) {
            senders.push(sender);
        }
    }
    for sender in senders {
        if replays.get() >= max_replays {
            break;
        }
        let candidate: Vec<_> = events
            .iter()
            .copied()
            .filter(|e| match e.input {
                Input::Command(c) => Some(c.client_id) != sender,
                Input::Bus(_) => sender.is_some(),
            })
            .collect();
        if let Some(v) = fails(&candidate) {
            events = candidate;
            violation = v;
        }
    }
    let mut n = 2usize;
    let mut budget_spent = false;
    while events.len() >= 2 {
        let chunk = events.len().div_ceil(n);
        let mut found = None;
        for i in 0..n {
            if replays.get() >= max_replays {
                budget_spent = true;
                break;
            }
            let (from, to) = (i * chunk, ((i + 1) * chunk).min(events.len()));
            if from >= to {
                continue;
            }
            let candidate: Vec<_> = events[..from]
                .iter()
                .chain(&events[to..])
                .copied()
                .collect();
            if let Some(v) = fails(&candidate) {
                found = Some((candidate, v));
                break;
            }
        }
        match found {
            Some((candidate, v)) => {
                events = candidate;
                violation = v;
                n = (n - 1).max(2);
            }
            None if budget_spent || n >= events.len() => break,
            None => n = (2 * n).min(events.len()),
        }
    }
    // A last try without any input at all (a failure of the world alone).
    if !budget_spent
        && events.len() == 1
        && let Some(v) = fails(&[])
    {
        events.clear();
        violation = v;
    }
    Some(Shrunk {
        script: Script {
            seed: script.seed,
            fault_kinds: script.fault_kinds,
            planted: script.planted,
            events,
        },
        violation,
        inputs_before,
        replays: replays.get(),
        budget_spent,
    })
}

#[cfg(test)]
mod tests;
