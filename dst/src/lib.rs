//! # mcm-dst: deterministic simulation testing of the whole controller
//!
//! Runs the real controller (command intake, ownership, modes, safety checks, CANopen master)
//! over the simulated bus, drives and arm physics in virtual time, single threaded, with
//! everything random drawn from one seed: the run's swarm options ([`swarm`]), its clients
//! ([`clients`]), its faults ([`faults`], bus faults in [`faulty_bus`]). Every cycle is
//! checked against the invariants ([`invariants`]) and hashed ([`hash`]), so that
//! `mcm-dst --seed N` replays a run bit for bit and names the first cycle where a replay
//! differs. [`campaign`] runs many seeds on several threads and counts what was reached;
//! [`fuzz_input`] runs a script that the fuzz target (`fuzz/`) builds from its bytes. See
//! `docs/testing.md`, "Deterministic simulation testing".
//!
//! Nothing here runs inside the real-time cycle; it drives the cycle ([`world::World::step`])
//! and counts what the cycle's work allocates.

pub mod campaign;
pub mod cli;
pub mod clients;
pub mod driver;
pub mod faults;
pub mod faulty_bus;
pub mod fuzz_input;
pub mod hash;
pub mod invariants;
pub mod rate;
pub mod rng;
pub mod run;
pub mod script;
pub mod shrink;
pub mod stamp;
pub mod swarm;
pub mod trace;
pub mod under_way;
pub mod world;
