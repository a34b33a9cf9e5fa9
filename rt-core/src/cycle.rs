//! One cycle of the real-time core against a bus: read the frames, step the controller, send
//! the frames; and between the steps, the lines of `move_linear` to and from their planner
//! ([`crate::line_planner`]). The cycle also owns the state sample it publishes, which
//! [`crate::publish::compose`] writes after the step (from [`crate::runner::run_cycle`]).
//!
//! Runs inside the cycle; used by the real-time loop ([`crate::runner`]) and, with virtual
//! time, by the deterministic tests (same inputs, same outputs, no wall clock). It knows
//! nothing of the simulator: with the simulated bus, the runner puts the simulator's edge
//! ([`crate::sim_edge`]) between [`Cycle::receive`] and [`Cycle::step`].
//!
//! ```
//! # #[cfg(feature = "sim")] { // the simulated bus comes with the `sim` feature
//! use mcm_rt_core::cycle::Cycle;
//! use mcm_sim::SimBus;
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let mut cycle = Cycle::new(&cfg, SimBus::new(&cfg)).unwrap();
//! for k in 0..10 {
//!     cycle.run(k * cfg.cycle_period_ns(), &[]);
//! }
//! assert_eq!(cycle.controller().view().cycle, 10);
//! # }
//! ```

use crate::canopen::{FrameBuf, Master, MasterSetupError};
use crate::cartesian::{Cartesian, CartesianSetupError};
use crate::controller::{Controller, CycleView};
use crate::line_planner::{LineJob, LinePlanner, joint_limits};
use crate::params::JointParams;
use mcm_bus::{Bus, Frame};
use mcm_shared::config::RobotConfig;
use mcm_shared::sample::{CommandSample, StateSample};

/// Frames read per cycle at most; more stay queued for the next cycle.
pub const RX_PER_CYCLE: usize = 128;
pub use mcm_shared::service::COMMANDS_PER_CYCLE;

/// Why the cycle cannot run with this configuration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CycleSetupError {
    #[error(transparent)]
    Master(#[from] MasterSetupError),
    #[error(transparent)]
    Cartesian(#[from] CartesianSetupError),
}

/// The controller and its bus.
pub struct Cycle<B: Bus> {
    controller: Controller,
    bus: B,
    rx: [Frame; RX_PER_CYCLE],
    /// Frames read by the last [`Cycle::receive`], not yet given to the controller.
    n_rx: usize,
    tx: FrameBuf,
    bus_errors: u64,
    /// The published state, composed after each step (kept for its reply ring).
    state: StateSample,
    /// Where the controller's lines are planned ([`crate::line_planner`]).
    planner: LinePlanner,
    /// A line the controller asked for while the planner was busy: handed over when it is
    /// free.
    line_waiting: Option<LineJob>,
}

impl<B: Bus> Cycle<B> {
    /// Build the CANopen master (which checks the bus load), the kinematics of the TCP (which
    /// refuse an arm they cannot handle) and the controller over `bus` with both.
    pub fn new(cfg: &RobotConfig, bus: B) -> Result<Self, CycleSetupError> {
        let master = Master::new(cfg)?;
        let cartesian = Cartesian::from_config(cfg)?;
        Ok(Self {
            controller: Controller::new(cfg, master, cartesian),
            bus,
            rx: [Frame::default(); RX_PER_CYCLE],
            n_rx: 0,
            tx: FrameBuf::new(),
            bus_errors: 0,
            state: StateSample::default(),
            planner: LinePlanner::inline(joint_limits(&JointParams::from_config(cfg))),
            line_waiting: None,
        })
    }

    /// Plan the controller's lines with `planner` (the runner's planner thread) instead of
    /// on the cycle's thread.
    pub fn plan_lines_with(&mut self, planner: LinePlanner) {
        self.planner = planner;
    }

    pub fn controller(&self) -> &Controller {
        &self.controller
    }

    /// The state sample as last composed.
    pub fn state(&self) -> &StateSample {
        &self.state
    }

    /// The replies the last cycle gave, oldest first (not numbered yet: the edge numbers them
    /// when it publishes them).
    pub fn replies(&self) -> &[mcm_shared::sample::Reply] {
        self.controller.view().replies.replies()
    }

    /// The controller's view of the last step, the state sample to compose from it and the
    /// kinematics of its TCP, the controller's, which follow its active tool (`set_tool`).
    pub fn publish_parts(&mut self) -> (&CycleView, &mut StateSample, &Cartesian) {
        (
            self.controller.view(),
            &mut self.state,
            self.controller.cartesian(),
        )
    }

    pub fn bus_mut(&mut self) -> &mut B {
        &mut self.bus
    }

    /// The controller and the bus at once (for an edge that works on both between
    /// [`Cycle::receive`] and [`Cycle::step`]).
    pub fn parts_mut(&mut self) -> (&mut Controller, &mut B) {
        (&mut self.controller, &mut self.bus)
    }

    /// Frames that could not be sent or received since start.
    pub fn bus_errors(&self) -> u64 {
        self.bus_errors
    }

    /// Run one cycle at controller time `now_ns` with `commands`: [`Cycle::receive`] then
    /// [`Cycle::step`].
    pub fn run(&mut self, now_ns: u64, commands: &[CommandSample]) {
        self.receive();
        self.step(now_ns, commands);
    }

    /// First half of a cycle: start the controller's outbox of replies and read the frames
    /// received since the last cycle (at most [`RX_PER_CYCLE`]; more stay queued).
    pub fn receive(&mut self) {
        self.controller.begin_cycle();
        let mut n_rx = 0;
        while n_rx < RX_PER_CYCLE {
            match self.bus.recv(0) {
                Ok(Some(f)) => {
                    self.rx[n_rx] = f;
                    n_rx += 1;
                }
                Ok(None) => break,
                Err(_) => {
                    self.bus_errors += 1;
                    break;
                }
            }
        }
        self.n_rx = n_rx;
    }

    /// Second half of a cycle: step the controller at controller time `now_ns` with the frames
    /// of the last [`Cycle::receive`] and `commands` (at most [`COMMANDS_PER_CYCLE`] are
    /// served; the caller keeps the rest for the next cycle), then send its frames.
    pub fn step(&mut self, now_ns: u64, commands: &[CommandSample]) {
        let n_rx = core::mem::take(&mut self.n_rx);
        let commands = &commands[..commands.len().min(COMMANDS_PER_CYCLE)];
        self.tx.clear();
        if let Some(planned) = self.planner.finished() {
            self.controller.line_planned(planned);
            self.planner.release();
        }
        self.controller
            .step(now_ns, &self.rx[..n_rx], commands, &mut self.tx);
        self.hand_over_line();
        for f in self.tx.iter() {
            if self.bus.send(f).is_err() {
                self.bus_errors += 1;
            }
        }
        self.controller.note_bus_errors(self.bus_errors);
    }

    /// Give the planner the line the controller asked for, with the kinematics of the active
    /// tool's TCP; one that finds the planner busy waits for the next cycle.
    fn hand_over_line(&mut self) {
        if let Some(request) = self.controller.take_line_request() {
            // The controller's kinematics follow its active tool (`Controller::use_tool`): the
            // line is planned for the TCP the state reports.
            self.line_waiting = Some(LineJob {
                request,
                kin: *self.controller.cartesian().kinematics(),
            });
        }
        if let Some(job) = &self.line_waiting
            && self.planner.post(job)
        {
            self.line_waiting = None;
        }
    }
}

#[cfg(test)]
mod tests;
