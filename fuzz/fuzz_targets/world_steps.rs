//! libFuzzer's entry: its bytes become, through `arbitrary`, an [`mcm_fuzz::Input`] (a robot and
//! steps of commands and bus faults), which `mcm_fuzz::run` drives through the deterministic
//! simulation tester's world, checking every cycle.
//!
//! `cargo +nightly fuzz run --features libfuzzer world_steps -- -max_total_time=120` (`docs/testing.md`,
//! "Deterministic simulation testing").

#![no_main]

use libfuzzer_sys::fuzz_target;
use mcm_shared::alloc_count::CountingAlloc;

// The checker's "no allocation in the cycle" counts through it.
#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

fuzz_target!(|input: mcm_fuzz::Input| {
    mcm_fuzz::run(&input);
});
