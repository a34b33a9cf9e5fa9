//! The fuzz input on stable, without the fuzzer: inputs made by `arbitrary` from a fixed
//! generator's bytes (as libFuzzer's would be) run through the world with no invariant broken,
//! and the world runs cycles and answers commands, so that the run exercises the controller and
//! not an idle arm. A change to the simulation tester's API that the fuzz target uses fails to
//! compile here; a command kind the inputs never send fails here.

use super::*;
use mcm_shared::alloc_count::CountingAlloc;
use std::collections::HashSet;

// The checker's "no allocation in the cycle" counts through it, as in the fuzz target.
#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

/// Inputs are drawn until the world has run this many cycles (a few steps each).
const CYCLES: u64 = 2_000;
/// At most this many inputs.
const INPUTS: usize = 200;

#[test]
fn inputs_from_arbitrary_bytes_run_with_no_invariant_broken() {
    let mut rng = Rng::new(0x5eed);
    let (mut inputs, mut cycles, mut answers) = (0, 0, 0);
    while cycles < CYCLES && inputs < INPUTS {
        let bytes: Vec<u8> = (0..4096).map(|_| rng.next_u64() as u8).collect();
        let input = Input::arbitrary_take_rest(Unstructured::new(&bytes))
            .expect("arbitrary makes an input of any bytes");
        let report = run(&input);
        inputs += 1;
        cycles += report.cycles;
        answers += report.answers.iter().sum::<u64>();
    }
    assert!(
        cycles >= CYCLES && answers >= 10,
        "{inputs} inputs drove the world {cycles} cycles and got {answers} answers: too little to \
         test anything"
    );
}

/// Every kind of `CommandKind::ALL` is among the commands the inputs send: a kind whose
/// arguments [`Cmd::of_kind`] draws as another kind's is never fuzzed, and fails here.
#[test]
fn every_command_kind_is_sent_by_the_inputs() {
    let ranges = Ranges::of(&RobotConfig::prob2_default());
    let mut rng = Rng::new(0x5eed);
    let mut sent = HashSet::new();
    for _ in 0..2_000 {
        let bytes: Vec<u8> = (0..256).map(|_| rng.next_u64() as u8).collect();
        let cmd = Cmd::arbitrary(&mut Unstructured::new(&bytes)).expect("a command of any bytes");
        if !matches!(cmd, Cmd::Raw { .. }) {
            sent.insert(cmd.sample(&ranges).kind);
        }
    }
    for kind in CommandKind::ALL {
        assert!(
            sent.contains(&kind.to_wire()),
            "no input sends {kind}: its arguments are not drawn"
        );
    }
}
