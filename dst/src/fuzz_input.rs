//! A scripted run, the fuzz target's input (`fuzz/fuzz_targets/world_steps.rs`): steps of
//! cycles, each with the commands its clients send and the bus faults from then on, run
//! through the [`World`] and checked every cycle by the [`Checker`], as [`crate::run`] runs a
//! seed. The fuzz target builds a [`Script`] from its bytes; what it may send, and how the
//! faults it injects with `sim` commands are told to the checker, is decided here, so that
//! the workspace's tests cover it (the fuzz crate is outside the workspace and not in CI).
//!
//! Nothing here runs inside the real-time cycle; it drives the cycle.

use crate::clients::FIRST_CLIENT_ID;
use crate::faults::Fault;
use crate::faulty_bus::BusFaults;
use crate::invariants::{Checker, Violation, Work};
use crate::rng::Rng;
use crate::stamp::Stamp;
use crate::world::World;
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Request, SimCommand};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode};
use mcm_shared::reply::{Outcome, Response};
use mcm_shared::sample::{CommandSample, Reply};
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
    let mut under_way = UnderWay::default();
    let mut bus = BusFaults::default();
    let mut faults = Vec::new();
    let mut cycle = |world: &mut World,
                     checker: &mut Checker,
                     under_way: &mut UnderWay,
                     bus: &BusFaults|
     -> Result<(), Violation> {
        faults.clear();
        under_way.faults(bus, &mut faults);
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
        checker.cycle(k, world.state(), world.replies(), work, &faults)?;
        under_way.answered(world.replies());
        Ok(())
    };
    'steps: for step in &script.steps {
        if let Some(b) = step.bus {
            bus = b;
            world.bus().faults = b;
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
                    under_way.sent(&c);
                    checker.asked(&c, k);
                    world.send(c);
                }
            }
            cycle(&mut world, &mut checker, &mut under_way, &bus)?;
        }
    }
    let end = world.cycle_index();
    while !checker.unanswered().is_empty() && world.cycle_index() - end < DRAIN_CYCLES {
        cycle(&mut world, &mut checker, &mut under_way, &bus)?;
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

/// The faults the script's `sim` commands put under way, for the checker (which excuses what
/// the arm does while a fault moves it, [`Fault::moves_the_arm`]).
///
/// The simulator applies a `sim` command when the cycle serves it and answers it in the same
/// cycle, in the order it serves them; so the state here follows the simulator's by applying
/// each command answered OK, in the order of the replies ([`SimBus`](mcm_sim::SimBus)'s
/// `apply`). Until it is answered, what a command starts counts as under way already (from
/// the cycle it is sent, as the fault schedule's started faults do), and what it undoes still
/// acts; a fault undone counts for the cycle of its answer too.
#[derive(Debug, Default)]
pub struct UnderWay {
    emergency_stop: bool,
    silent: [bool; NUM_AXES],
    blocked: [bool; NUM_AXES],
    pushed: bool,
    /// `sim` commands sent and not answered: (client, request, command).
    pending: Vec<(u64, u64, SimCommand)>,
}

impl UnderWay {
    /// A sample is sent: a well-formed `sim` command is pending until answered.
    pub fn sent(&mut self, c: &CommandSample) {
        if let Ok(Request::Sim(cmd)) = Request::decode(c) {
            self.pending.push((c.client_id, c.request_id, cmd));
        }
    }

    /// A cycle's replies: the `sim` commands answered OK act from now on.
    pub fn answered(&mut self, replies: &[Reply]) {
        for r in replies {
            let Some(i) = self
                .pending
                .iter()
                .position(|&(c, q, _)| c == r.client_id && q == r.request_id)
            else {
                continue;
            };
            let (_, _, cmd) = self.pending.remove(i);
            let done = Response::decode(r).is_ok_and(|x| matches!(x.outcome, Outcome::Done(_)));
            if done {
                self.apply(&cmd);
            }
        }
    }

    fn apply(&mut self, cmd: &SimCommand) {
        if let Some(pressed) = cmd.emergency_stop {
            self.emergency_stop = pressed;
        }
        if let Some(a) = cmd.disconnect_axis {
            self.silent[a.index()] = true;
        }
        if let Some(a) = cmd.reconnect_axis {
            self.silent[a.index()] = false;
        }
        if let Some(a) = cmd.block_axis {
            self.blocked[a.index()] = true;
        }
        if let Some(a) = cmd.unblock_axis {
            self.blocked[a.index()] = false;
        }
        if let Some(tau) = cmd.external_torques_nm {
            self.pushed = tau.iter().any(|t| *t != 0.0);
        }
    }

    /// The faults under way now, with the bus faults `bus` (named in a violation), into `out`.
    pub fn faults(&self, bus: &BusFaults, out: &mut Vec<Fault>) {
        let pending = |f: fn(&SimCommand) -> bool| self.pending.iter().any(|(_, _, c)| f(c));
        let mut add = |on: bool, f: Fault| {
            if on && !out.contains(&f) {
                out.push(f);
            }
        };
        add(
            self.emergency_stop || pending(|c| c.emergency_stop == Some(true)),
            Fault::EmergencyStop,
        );
        add(
            self.silent.iter().any(|s| *s) || pending(|c| c.disconnect_axis.is_some()),
            Fault::DriveSilent,
        );
        add(
            self.blocked.iter().any(|b| *b) || pending(|c| c.block_axis.is_some()),
            Fault::Obstacle,
        );
        add(
            self.pushed
                || pending(|c| {
                    c.external_torques_nm
                        .is_some_and(|t| t.iter().any(|x| *x != 0.0))
                }),
            Fault::Push,
        );
        add(pending(|c| c.power_cycle), Fault::PowerCycle);
        add(bus.lose_rx > 0.0 || bus.lose_tx > 0.0, Fault::BusLoss);
        add(bus.corrupt_rx > 0.0, Fault::BusCorruption);
        add(bus.delay_rx > 0.0, Fault::BusDelay);
        add(bus.duplicate_rx > 0.0, Fault::BusDuplication);
        add(bus.lose_heartbeats_of.is_some(), Fault::HeartbeatLoss);
    }
}

#[cfg(test)]
mod tests;
