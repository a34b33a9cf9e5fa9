//! A scripted run, the fuzz target's input (`fuzz/fuzz_targets/world_steps.rs`): steps of
//! cycles, each with the commands its clients send and the bus faults from then on, run
//! through the [`World`] and checked every cycle by the [`Checker`], as [`crate::run`] runs a
//! seed. The fuzz target builds a [`Script`] from its bytes; what it may send, and how the
//! faults it injects with `sim` commands are told to the checker, is decided here, so that
//! the workspace's tests cover it (the fuzz crate is outside the workspace and not in CI).
//!
//! Nothing here runs inside the real-time cycle; it drives the cycle.

use crate::clients::FIRST_CLIENT_ID;
use crate::faulty_bus::BusFaults;
use crate::invariants::{Checker, Violation, Work};
use crate::rng::Rng;
use crate::stamp::Stamp;
use crate::world::World;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode};
use mcm_shared::sample::CommandSample;
use std::collections::VecDeque;

/// Clients a script sends from. Each is a connection: after its `client_gone` it sends with a
/// new id. Fewer than the intake serves in a cycle, as the checker's answer bound assumes
/// ([`crate::invariants::QUEUE_CYCLES`]).
pub const SCRIPT_CLIENTS: usize = 4;

/// Cycles run after the last step, at most, while commands are still unanswered: the longest
/// an answer may take but a calibration's (the drives' enabling, 2 s at 200 Hz, plus the
/// intake's queue).
pub const DRAIN_CYCLES: u64 = 500;

/// A scripted run.
#[derive(Debug, Clone)]
pub struct Script {
    /// The robot (its encoder offsets, its start pose: [`crate::run::config`] draws one).
    pub cfg: RobotConfig,
    /// Seeds the faulty bus's randomness.
    pub bus_seed: u64,
    pub steps: Vec<Step>,
}

/// One step of a script.
#[derive(Debug, Clone, Default)]
pub struct Step {
    /// Cycles to run. A client sends at most one command a cycle (as a run's clients do, and
    /// as the checker's answer bound assumes): its second command of the step goes a cycle
    /// after its first, and a step with more commands of one client than cycles runs as many
    /// cycles as that client has commands.
    pub cycles: u32,
    /// The samples sent, each by a client ([`SCRIPT_CLIENTS`] of them: the index is taken
    /// modulo), stamped with its id and its next request id when sent.
    pub commands: Vec<(usize, CommandSample)>,
    /// The bus faults from this step on (`None`: as they were).
    pub bus: Option<BusFaults>,
}

/// How far a script runs, and what is checked.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// Cycles of the steps at most (the rest of a longer script is not run), not counting the
    /// drain ([`DRAIN_CYCLES`]).
    pub max_cycles: u64,
    /// Check the cycle's work against its CPU budget. Off under a fuzzer's instrumentation
    /// (sanitizer and coverage counters make the work several times slower than the build
    /// the budget is for).
    pub cpu_budget: bool,
}

/// What a script did (when no invariant broke).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ScriptReport {
    pub cycles: u64,
    /// [`Checker::modes_reached`].
    pub modes_reached: [u64; Mode::ALL.len()],
    /// [`Checker::answers`]: OK, refused, failed.
    pub answers: [u64; 3],
}

/// Run `script`, checking every cycle; the first broken invariant is the error.
pub fn run_script(script: &Script, limits: Limits) -> Result<ScriptReport, Violation> {
    let mut world = World::new(&script.cfg, Rng::new(script.bus_seed));
    let mut checker = Checker::new(&script.cfg, world.bus().sim());
    let mut clients: [Sender; SCRIPT_CLIENTS] = core::array::from_fn(Sender::new);
    let cycle = |world: &mut World, checker: &mut Checker| -> Result<(), Violation> {
        world.step();
        let k = world.cycle_index();
        let work = Work {
            allocations: std::mem::take(&mut world.allocations),
            cpu_ns: if limits.cpu_budget {
                world.last_cpu_ns
            } else {
                0
            },
        };
        checker.cycle(
            k,
            world.state(),
            world.replies(),
            world.served(),
            work,
            world.faults(),
        )
    };
    'steps: for step in &script.steps {
        if let Some(b) = step.bus {
            world.set_bus_faults(b);
        }
        let mut queues: [VecDeque<CommandSample>; SCRIPT_CLIENTS] = Default::default();
        for (client, c) in &step.commands {
            queues[client % SCRIPT_CLIENTS].push_back(*c);
        }
        let longest = queues.iter().map(VecDeque::len).max().unwrap_or(0);
        let cycles = (step.cycles.max(1) as usize).max(longest);
        for _ in 0..cycles {
            if world.cycle_index() >= limits.max_cycles {
                break 'steps;
            }
            let k = world.cycle_index();
            for (sender, queue) in clients.iter_mut().zip(&mut queues) {
                if let Some(c) = queue.pop_front() {
                    let c = sender.send(c);
                    checker.asked(&c, k);
                    world.send(c);
                }
            }
            cycle(&mut world, &mut checker)?;
        }
    }
    let end = world.cycle_index();
    while !checker.unanswered().is_empty() && world.cycle_index() - end < DRAIN_CYCLES {
        cycle(&mut world, &mut checker)?;
    }
    Ok(ScriptReport {
        cycles: world.cycle_index(),
        modes_reached: checker.modes_reached,
        answers: checker.answers,
    })
}

/// One of the script's clients: its slot and its connection's stamp.
struct Sender {
    slot: usize,
    connection: u64,
    stamp: Stamp,
}

impl Sender {
    fn new(slot: usize) -> Sender {
        Sender {
            slot,
            connection: 0,
            stamp: Stamp::new(Self::id(slot, 0)),
        }
    }

    /// Ids from [`FIRST_CLIENT_ID`] on, distinct for every slot and connection.
    fn id(slot: usize, connection: u64) -> u64 {
        FIRST_CLIENT_ID + slot as u64 + SCRIPT_CLIENTS as u64 * connection
    }

    /// `c` stamped; after a `client_gone` the next command comes from a new connection.
    fn send(&mut self, c: CommandSample) -> CommandSample {
        let c = self.stamp.stamp(c);
        if c.kind == CommandKind::ClientGone.to_wire() {
            self.connection += 1;
            self.stamp = Stamp::new(Self::id(self.slot, self.connection));
        }
        c
    }
}

#[cfg(test)]
mod tests;
