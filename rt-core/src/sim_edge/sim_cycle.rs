//! [`SimCycle`]: the cycle over `mcm-sim`'s simulated bus with the simulator's edge, as the
//! runner composes them (only with the `sim` feature).
//!
//! Runs inside the cycle (`SimCycle::run` in virtual time, for the tests and the benchmarks).

use super::SimEdge;
use crate::controller::Controller;
use crate::cycle::{Cycle, CycleSetupError};
use crate::publish::CycleClock;
use mcm_shared::config::RobotConfig;
use mcm_shared::sample::{CommandSample, StateSample};
use mcm_sim::SimBus;

/// The simulated robot in virtual time: `Cycle<B>` with the simulator's edge, stepped by the
/// runner's own [`crate::runner::run_cycle`] (for tests and benchmarks). `B` is the simulator's
/// [`SimBus`], or a bus that wraps it (the deterministic simulation's faulty cable:
/// [`SimCycle::over`]). The cycle (about 230 kB) lives on the heap so that a test can hold
/// several robots on its thread's stack.
///
/// ```
/// use mcm_rt_core::sim_edge::SimCycle;
/// use mcm_shared::command::{Request, SimCommand};
/// use mcm_shared::reply::{Done, Outcome, Response};
/// use mcm_shared::sample::{STATE_SIM_ESTOP, STATE_SIMULATED};
/// let cfg = mcm_shared::config::RobotConfig::prob2_default();
/// let mut robot = SimCycle::new(&cfg, mcm_sim::SimBus::new(&cfg)).unwrap();
/// let press = SimCommand { emergency_stop: Some(true), ..SimCommand::default() };
/// let mut sample = Request::Sim(press).encode();
/// (sample.client_id, sample.request_id) = (1, 7);
/// robot.run(0, &[sample]);
/// let s = robot.state();
/// let reply = Response::decode(robot.replies().last().unwrap()).unwrap();
/// assert_eq!((reply.request_id, reply.outcome), (7, Outcome::Done(Done::Ack)));
/// assert_ne!(s.flags & STATE_SIMULATED, 0);
/// assert_ne!(s.flags & STATE_SIM_ESTOP, 0);
/// ```
pub struct SimCycle<B: mcm_bus::Bus = SimBus> {
    cycle: Box<Cycle<B>>,
    edge: SimEdge<B>,
    period_ns: u64,
}

impl SimCycle {
    /// The controller over `bus`, with the edge (see [`Cycle::new`]).
    pub fn new(cfg: &RobotConfig, bus: SimBus) -> Result<Self, CycleSetupError> {
        Self::over(cfg, bus, |b| b)
    }
}

impl<B: mcm_bus::Bus> SimCycle<B> {
    /// The controller over `bus`, a bus with the simulated robot inside that the edge reaches
    /// through `sim` (see [`Cycle::new`]).
    pub fn over(
        cfg: &RobotConfig,
        bus: B,
        sim: super::SimAccess<B>,
    ) -> Result<Self, CycleSetupError> {
        Ok(Self {
            cycle: Box::new(Cycle::new(cfg, bus)?),
            edge: SimEdge::new(sim),
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
    pub fn bus_mut(&mut self) -> &mut B {
        self.cycle.bus_mut()
    }
}
