//! The simulator's edge: the only place where the simulated robot (`mcm-sim`) meets the cycle.
//!
//! Runs inside the cycle: no allocation, no locks, no I/O, no logging. Only the runner wires
//! it in, for `bus.backend = "sim"` ([`crate::runner::run_cycle`]); with real drives there is
//! no edge and a `sim` command reaches the controller, which refuses it as `not_simulated`.
//!
//! The edge reaches the simulated robot through the contract's [`SimControl`]
//! (`mcm_shared::simulator`), which `mcm-sim`'s `SimBus` implements. `mcm-sim` is a dependency
//! of this crate only with this crate's `sim` feature (on by default; it also brings
//! `SimCycle`). Without the feature there is no simulated robot to reach, and the runner
//! refuses `bus.backend = "sim"` ([`crate::runner::RunError::SimNotBuilt`]).
//!
//! Per cycle, between [`Cycle::receive`] and [`Cycle::step`] (where the frames the injection
//! makes the drives send are read in the next cycle, as on a real bus): the samples that decode
//! as `sim` requests are taken out of the commands, applied to the simulated robot
//! ([`SimControl::apply`]), and their replies added to the controller's outbox of this cycle
//! (a refusal as the [`Reason`] its error maps to); the other commands, a `sim` sample that
//! does not decode among them, go to the controller. After the step the edge yields the
//! simulation's truth ([`SimTruth`]), which the composer of the state sample
//! ([`crate::publish`]) reads.
//!
//! `SimCycle` composes `Cycle<SimBus>` with the edge exactly as the runner does, for the
//! deterministic tests and the benchmarks (virtual time).

use crate::controller::Controller;
use crate::cycle::{COMMANDS_PER_CYCLE, Cycle};
use mcm_bus::Bus;
use mcm_shared::command::{Request, SimCommand};
use mcm_shared::mode::CommandKind;
use mcm_shared::reply::{Done, Outcome, Reason, Response};
use mcm_shared::sample::CommandSample;
use mcm_shared::simulator::{SimControl, SimTruth};

/// How the edge reaches the simulated robot inside the bus the runner built.
pub type SimAccess<B> = fn(&mut B) -> &mut dyn SimControl;

/// The simulator's edge around the cycles over a bus `B` that is (or wraps) the simulator.
pub struct SimEdge<B: Bus> {
    sim: SimAccess<B>,
    pass: [CommandSample; COMMANDS_PER_CYCLE],
}

impl<B: Bus> SimEdge<B> {
    /// The edge reaching the simulator through `sim` (e.g. `|b: &mut SimBus| b`).
    pub fn new(sim: SimAccess<B>) -> Self {
        Self {
            sim,
            pass: [CommandSample::default(); COMMANDS_PER_CYCLE],
        }
    }

    /// One cycle of `cycle` at controller time `now_ns` with `commands` (at most
    /// [`COMMANDS_PER_CYCLE`] are served), with the `sim` commands served by the edge; the
    /// simulation's truth after the cycle.
    pub fn run(
        &mut self,
        cycle: &mut Cycle<B>,
        now_ns: u64,
        commands: &[CommandSample],
    ) -> SimTruth {
        cycle.receive();
        let (controller, bus) = cycle.parts_mut();
        let sim = (self.sim)(bus);
        let mut n_pass = 0;
        for c in commands.iter().take(COMMANDS_PER_CYCLE) {
            // A `sim` sample that does not decode goes on to the controller, which refuses
            // every undecodable sample the same way.
            match sim_request(c) {
                Some(cmd) => serve(sim, controller, c, &cmd),
                None => {
                    self.pass[n_pass] = *c;
                    n_pass += 1;
                }
            }
        }
        cycle.step(now_ns, &self.pass[..n_pass]);
        (self.sim)(cycle.bus_mut()).truth()
    }
}

/// The fault injection a sample carries, if it is a well-formed `sim` sample.
fn sim_request(c: &CommandSample) -> Option<SimCommand> {
    if c.kind != CommandKind::Sim.to_wire() {
        return None;
    }
    match Request::decode(c) {
        Ok(Request::Sim(cmd)) => Some(cmd),
        _ => None,
    }
}

/// Apply one `sim` command to the simulator and answer it: done, or refused as the simulator
/// says.
fn serve(
    sim: &mut dyn SimControl,
    controller: &mut Controller,
    c: &CommandSample,
    cmd: &SimCommand,
) {
    let outcome = match sim.apply(cmd) {
        Ok(()) => Outcome::Done(Done::Ack),
        Err(e) => Outcome::Refused(Reason::from(e)),
    };
    let r = Response {
        client_id: c.client_id,
        request_id: c.request_id,
        kind: CommandKind::Sim,
        outcome,
    };
    controller.answer(r.encode());
}

#[cfg(feature = "sim")]
mod sim_cycle;
#[cfg(feature = "sim")]
pub use sim_cycle::SimCycle;
