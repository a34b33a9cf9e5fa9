//! The simulator's edge: the only place where the simulated robot (`mcm-sim`) meets the cycle.
//!
//! Runs inside the cycle: no allocation, no locks, no I/O, no logging. Only the runner wires
//! it in, for `bus.backend = "sim"` ([`crate::runner::run_cycle`]); with real drives there is
//! no edge and a `sim` command reaches the controller, which refuses it as `not_simulated`.
//!
//! Per cycle, between [`Cycle::receive`] and [`Cycle::step`] (where the frames the injection
//! makes the drives send are read in the next cycle, as on a real bus): the samples that decode
//! as `sim` requests are taken out of the commands, applied to the simulator's control surface
//! ([`SimControl`]), and their replies added to the controller's outbox of this cycle; the
//! other commands, a `sim` sample that does not decode among them, go to the controller. After the step the edge yields the simulation's truth,
//! which the composer of the state sample ([`crate::publish`]) reads.
//!
//! [`SimCycle`] composes `Cycle<SimBus>` with the edge exactly as the runner does, for the
//! deterministic tests and the benchmarks (virtual time).
//!
//! ```
//! use mcm_rt_core::sim_edge::SimCycle;
//! use mcm_shared::command::{Request, SimCommand};
//! use mcm_shared::reply::{Done, Outcome, Response};
//! use mcm_shared::sample::{STATE_SIM_ESTOP, STATE_SIMULATED};
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let mut robot = SimCycle::new(&cfg, mcm_sim::SimBus::new(&cfg)).unwrap();
//! let press = SimCommand { emergency_stop: Some(true), ..SimCommand::default() };
//! let mut sample = Request::Sim(press).encode();
//! (sample.client_id, sample.request_id) = (1, 7);
//! robot.run(0, &[sample]);
//! let s = robot.state();
//! let reply = Response::decode(robot.replies().last().unwrap()).unwrap();
//! assert_eq!((reply.request_id, reply.outcome), (7, Outcome::Done(Done::Ack)));
//! assert_ne!(s.flags & STATE_SIMULATED, 0);
//! assert_ne!(s.flags & STATE_SIM_ESTOP, 0);
//! ```

use crate::canopen::MasterSetupError;
use crate::controller::Controller;
use crate::cycle::{COMMANDS_PER_CYCLE, Cycle};
use crate::publish::CycleClock;
use mcm_bus::Bus;
use mcm_shared::command::{Axis, Request, SimCommand};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::CommandKind;
use mcm_shared::reply::{Done, Outcome, Reason, Response};
use mcm_shared::sample::{CommandSample, StateSample};
use mcm_sim::{SimBus, SimCommandError, SimControl, SimTruth};

/// How the edge reaches the simulator's control surface inside the bus the runner built.
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

/// Apply one `sim` command to the simulator and answer it: done, or `out_of_range` naming the
/// value the simulator refused.
fn serve(
    sim: &mut dyn SimControl,
    controller: &mut Controller,
    c: &CommandSample,
    cmd: &SimCommand,
) {
    let outcome = match sim.apply(cmd) {
        Ok(()) => Outcome::Done(Done::Ack),
        Err(SimCommandError::TorqueNotFinite { index, value }) => {
            Outcome::Refused(Reason::OutOfRange {
                axis: Axis::from_index(index),
                value,
                min: f64::MIN,
                max: f64::MAX,
            })
        }
    };
    let r = Response {
        client_id: c.client_id,
        request_id: c.request_id,
        kind: CommandKind::Sim,
        outcome,
    };
    controller.answer(r.encode());
}

/// The simulated robot in virtual time: `Cycle<SimBus>` with the simulator's edge, stepped by
/// the runner's own [`crate::runner::run_cycle`] (for tests and benchmarks). The cycle (about
/// 230 kB) lives on the heap so that a test can hold several robots on its thread's stack.
pub struct SimCycle {
    cycle: Box<Cycle<SimBus>>,
    edge: SimEdge<SimBus>,
    period_ns: u64,
}

impl SimCycle {
    /// The controller over `bus`, with the edge (see [`Cycle::new`]).
    pub fn new(cfg: &RobotConfig, bus: SimBus) -> Result<Self, MasterSetupError> {
        Ok(Self {
            cycle: Box::new(Cycle::new(cfg, bus)?),
            edge: SimEdge::new(|b| b),
            period_ns: cfg.cycle_period_ns(),
        })
    }

    /// One cycle at controller time `now_ns`, as the real-time loop runs it; the state's
    /// `t_ns` is the same virtual time.
    pub fn run(&mut self, now_ns: u64, commands: &[CommandSample]) {
        let clock = CycleClock::virtual_time(now_ns, self.period_ns);
        crate::runner::run_cycle(
            &mut self.cycle,
            Some(&mut self.edge),
            now_ns,
            &clock,
            commands,
        );
    }

    /// The state sample as last composed.
    pub fn state(&self) -> &StateSample {
        self.cycle.state()
    }

    /// The replies of the last cycle ([`Cycle::replies`]).
    pub fn replies(&self) -> &[mcm_shared::sample::Reply] {
        self.cycle.replies()
    }

    pub fn controller(&self) -> &Controller {
        self.cycle.controller()
    }

    /// The controller, to drive what the runner drives between cycles (a shutdown).
    pub fn controller_mut(&mut self) -> &mut Controller {
        self.cycle.parts_mut().0
    }

    /// The simulated robot (inspection, save/resume, direct fault injection).
    pub fn bus_mut(&mut self) -> &mut SimBus {
        self.cycle.bus_mut()
    }
}
