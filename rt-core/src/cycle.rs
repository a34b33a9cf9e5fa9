//! One cycle of the real-time core against a bus: read the frames, serve the simulation's
//! fault injection, step the controller, send the frames.
//!
//! Runs inside the cycle; used by the real-time loop ([`crate::runner`]) and, with virtual
//! time, by the deterministic tests (same inputs, same outputs, no wall clock).
//!
//! ```
//! use mcm_rt_core::cycle::Cycle;
//! use mcm_rt_core::sim::SimBus;
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let mut cycle = Cycle::new(&cfg, SimBus::new(&cfg)).unwrap();
//! for k in 0..10 {
//!     cycle.run(k * cfg.cycle_period_ns(), &[]);
//! }
//! assert_eq!(cycle.controller().state().seq, 10);
//! ```

use crate::bus::{Bus, Frame};
use crate::canopen::{FrameBuf, Master, MasterSetupError};
use crate::controller::Controller;
use crate::request::{self, Request};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, RejectCode, ReplyStatus};
use mcm_shared::sample::{CommandSample, REPLY_RING, Reply, STATE_SIM_ESTOP};

/// Frames read per cycle at most; more stay queued for the next cycle.
pub const RX_PER_CYCLE: usize = 128;
/// Commands served per cycle at most (each may produce a reply; the reply ring must hold a
/// whole cycle's replies).
pub const COMMANDS_PER_CYCLE: usize = REPLY_RING / 2;

/// The controller and its bus.
pub struct Cycle<B: Bus> {
    controller: Controller,
    bus: B,
    rx: [Frame; RX_PER_CYCLE],
    tx: FrameBuf,
    pass: [CommandSample; COMMANDS_PER_CYCLE],
    bus_errors: u64,
}

impl<B: Bus> Cycle<B> {
    /// Build the CANopen master (which checks the bus load) and the controller over `bus`.
    pub fn new(cfg: &RobotConfig, mut bus: B) -> Result<Self, MasterSetupError> {
        let master = Master::new(cfg)?;
        let simulated = bus.sim().is_some();
        Ok(Self {
            controller: Controller::new(cfg, master, simulated),
            bus,
            rx: [Frame::default(); RX_PER_CYCLE],
            tx: FrameBuf::new(),
            pass: [CommandSample::default(); COMMANDS_PER_CYCLE],
            bus_errors: 0,
        })
    }

    pub fn controller(&self) -> &Controller {
        &self.controller
    }

    pub fn controller_mut(&mut self) -> &mut Controller {
        &mut self.controller
    }

    pub fn bus_mut(&mut self) -> &mut B {
        &mut self.bus
    }

    /// Frames that could not be sent or received since start.
    pub fn bus_errors(&self) -> u64 {
        self.bus_errors
    }

    /// Run one cycle at controller time `now_ns` with `commands` (at most
    /// [`COMMANDS_PER_CYCLE`] are served; the caller keeps the rest for the next cycle).
    pub fn run(&mut self, now_ns: u64, commands: &[CommandSample]) {
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
        let mut n_pass = 0;
        for c in commands.iter().take(COMMANDS_PER_CYCLE) {
            if c.kind == CommandKind::Sim.to_wire() && self.bus.sim().is_some() {
                self.serve_sim(c);
            } else {
                self.pass[n_pass] = *c;
                n_pass += 1;
            }
        }
        self.tx.clear();
        self.controller
            .step(now_ns, &self.rx[..n_rx], &self.pass[..n_pass], &mut self.tx);
        for f in self.tx.iter() {
            if self.bus.send(f).is_err() {
                self.bus_errors += 1;
            }
        }
        if let Some(sim) = self.bus.sim() {
            let truth = sim.truth();
            let s = self.controller.state_mut();
            s.sim_true_position = truth.position.map(f64::to_degrees);
            s.sim_true_velocity = truth.velocity.map(f64::to_degrees);
            if truth.emergency_stop {
                s.flags |= STATE_SIM_ESTOP;
            } else {
                s.flags &= !STATE_SIM_ESTOP;
            }
        }
    }

    fn serve_sim(&mut self, c: &CommandSample) {
        let mut reply = Reply {
            client_id: c.client_id,
            request_id: c.request_id,
            kind: c.kind,
            ..Reply::default()
        };
        let result = match request::decode(c) {
            Ok(Request::Sim(cmd)) => match self.bus.sim().map(|s| s.apply(&cmd)) {
                Some(Ok(())) => Ok(()),
                Some(Err(_)) | None => Err((RejectCode::OutOfRange, 0, [0.0; 3])),
            },
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
        self.controller.push_reply(reply);
    }
}
