//! The simulator's edge: the only place where the simulated robot (`mcm-sim`) meets the cycle.
//!
//! Runs inside the cycle: no allocation, no locks, no I/O, no logging. Only the runner wires
//! it in, for `bus.backend = "sim"` ([`crate::runner::run_cycle`]); with real drives there is
//! no edge and a `sim` command reaches the controller, which refuses it as `not_simulated`.
//!
//! Per cycle, between [`Cycle::receive`] and [`Cycle::step`] (where the frames the injection
//! makes the drives send are read in the next cycle, as on a real bus): the `sim` command
//! samples are taken out of the commands, applied to the simulator's control surface
//! ([`SimControl`]), and their replies pushed into the controller's reply ring; the other
//! commands go to the controller. After the step the edge yields the simulation's truth, from
//! which the runner fills the state sample ([`crate::runner::fill_sim_fields`]).
//!
//! [`SimCycle`] composes `Cycle<SimBus>` with the edge exactly as the runner does, for the
//! deterministic tests and the benchmarks (virtual time).
//!
//! ```
//! use mcm_rt_core::sim_edge::SimCycle;
//! use mcm_shared::mode::{CommandKind, ReplyStatus};
//! use mcm_shared::sample::{CommandSample, STATE_SIM_ESTOP, STATE_SIMULATED};
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let mut robot = SimCycle::new(&cfg, mcm_sim::SimBus::new(&cfg)).unwrap();
//! let mut press = CommandSample { client_id: 1, request_id: 7, ..CommandSample::default() };
//! press.kind = CommandKind::Sim.to_wire();
//! press.flags = 1; // emergency_stop given ...
//! press.args[0] = 1.0; // ... and pressed
//! robot.run(0, &[press]);
//! let s = robot.controller().state();
//! assert_eq!(s.reply(s.reply_head).unwrap().status, ReplyStatus::Ok.to_wire());
//! assert_ne!(s.flags & STATE_SIMULATED, 0);
//! assert_ne!(s.flags & STATE_SIM_ESTOP, 0);
//! ```

use crate::canopen::MasterSetupError;
use crate::controller::Controller;
use crate::cycle::{COMMANDS_PER_CYCLE, Cycle};
use crate::request::{self, Request};
use mcm_bus::Bus;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, RejectCode, ReplyStatus};
use mcm_shared::sample::{CommandSample, Reply};
use mcm_sim::{SimBus, SimControl, SimTruth};

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
            if c.kind == CommandKind::Sim.to_wire() {
                serve(sim, controller, c);
            } else {
                self.pass[n_pass] = *c;
                n_pass += 1;
            }
        }
        cycle.step(now_ns, &self.pass[..n_pass]);
        (self.sim)(cycle.bus_mut()).truth()
    }
}

/// Apply one `sim` command to the simulator and push its reply: `ok`, or refused with the
/// decoder's reason, or `out_of_range` when the simulator refuses the argument.
fn serve(sim: &mut dyn SimControl, controller: &mut Controller, c: &CommandSample) {
    let mut reply = Reply {
        client_id: c.client_id,
        request_id: c.request_id,
        kind: c.kind,
        ..Reply::default()
    };
    let result = match request::decode(c) {
        Ok(Request::Sim(cmd)) => sim
            .apply(&cmd)
            .map_err(|_| (RejectCode::OutOfRange, 0, [0.0; 3])),
        Ok(_) => Err((RejectCode::OutOfRange, 0, [0.0; 3])),
        Err(e) => Err((e.code, e.axis, e.values)),
    };
    match result {
        Ok(()) => reply.status = ReplyStatus::Ok.to_wire(),
        Err((code, axis, values)) => {
            reply.status = ReplyStatus::Rejected.to_wire();
            reply.code = code.to_wire();
            reply.axis = axis;
            reply.values[..3].copy_from_slice(&values);
        }
    }
    controller.push_reply(reply);
}

/// The simulated robot in virtual time: `Cycle<SimBus>` with the simulator's edge, stepped by
/// the runner's own [`crate::runner::run_cycle`] (for tests and benchmarks). The cycle (about
/// 230 kB) lives on the heap so that a test can hold several robots on its thread's stack.
pub struct SimCycle {
    cycle: Box<Cycle<SimBus>>,
    edge: SimEdge<SimBus>,
}

impl SimCycle {
    /// The controller over `bus`, with the edge (see [`Cycle::new`]).
    pub fn new(cfg: &RobotConfig, bus: SimBus) -> Result<Self, MasterSetupError> {
        Ok(Self {
            cycle: Box::new(Cycle::new(cfg, bus)?),
            edge: SimEdge::new(|b| b),
        })
    }

    /// One cycle at controller time `now_ns`, as the real-time loop runs it.
    pub fn run(&mut self, now_ns: u64, commands: &[CommandSample]) {
        crate::runner::run_cycle(&mut self.cycle, Some(&mut self.edge), now_ns, commands);
    }

    pub fn controller(&self) -> &Controller {
        self.cycle.controller()
    }

    pub fn controller_mut(&mut self) -> &mut Controller {
        self.cycle.controller_mut()
    }

    /// The simulated robot (inspection, save/resume, direct fault injection).
    pub fn bus_mut(&mut self) -> &mut SimBus {
        self.cycle.bus_mut()
    }
}
