//! The faults of a run: what the simulated robot can suffer (emergency stop, a drive's cable
//! pulled, an obstacle, a hand pushing, the drives' power switched off and on) through `sim`
//! commands as a client sends them, and bus faults ([`BusFaults`]) set on the faulty bus.
//!
//! Each kind of fault comes in episodes: it starts at a random cycle (any mode, calibration
//! and braking included) and is undone after a random duration. Which kinds a run uses and how
//! often is its [`Swarm`](crate::swarm::Swarm)'s choice.

use crate::faulty_bus::BusFaults;
use crate::rng::Rng;
use crate::stamp::Stamp;
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Axis, Request, SimCommand};
use mcm_shared::sample::CommandSample;

/// The largest torque a push puts on its joint [Nm].
pub const PUSH_MAX_NM: f64 = 15.0;

/// The kinds of fault, for the schedule and the campaign's counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Fault {
    EmergencyStop,
    DriveSilent,
    Obstacle,
    Push,
    PowerCycle,
    BusLoss,
    BusCorruption,
    BusDelay,
    BusDuplication,
    HeartbeatLoss,
}

impl Fault {
    pub const ALL: [Fault; 10] = [
        Fault::EmergencyStop,
        Fault::DriveSilent,
        Fault::Obstacle,
        Fault::Push,
        Fault::PowerCycle,
        Fault::BusLoss,
        Fault::BusCorruption,
        Fault::BusDelay,
        Fault::BusDuplication,
        Fault::HeartbeatLoss,
    ];

    pub fn index(self) -> usize {
        Fault::ALL.iter().position(|f| *f == self).expect("listed")
    }

    pub fn name(self) -> &'static str {
        match self {
            Fault::EmergencyStop => "emergency_stop",
            Fault::DriveSilent => "drive_silent",
            Fault::Obstacle => "obstacle",
            Fault::Push => "push",
            Fault::PowerCycle => "power_cycle",
            Fault::BusLoss => "bus_loss",
            Fault::BusCorruption => "bus_corruption",
            Fault::BusDelay => "bus_delay",
            Fault::BusDuplication => "bus_duplication",
            Fault::HeartbeatLoss => "heartbeat_loss",
        }
    }

    fn is_bus(self) -> bool {
        matches!(
            self,
            Fault::BusLoss
                | Fault::BusCorruption
                | Fault::BusDelay
                | Fault::BusDuplication
                | Fault::HeartbeatLoss
        )
    }
}

/// One fault under way: its kind, the axis it concerns, the cycle it ends.
#[derive(Debug, Clone, Copy)]
struct Episode {
    fault: Fault,
    axis: Axis,
    until: u64,
}

/// What the schedule does this cycle.
#[derive(Debug, Default)]
pub struct Injection {
    /// `sim` commands to send (as the fault injector's client).
    pub commands: Vec<CommandSample>,
    /// The bus faults from now on, when they change.
    pub bus: Option<BusFaults>,
    /// Faults that started this cycle.
    pub started: Vec<Fault>,
}

/// The fault schedule of a run.
#[derive(Debug)]
pub struct Schedule {
    /// Chance per cycle that each enabled kind starts an episode (when none of it runs).
    rates: [f64; Fault::ALL.len()],
    active: Vec<Episode>,
    stamp: Stamp,
}

impl Schedule {
    /// `rates[f.index()]`: chance per cycle of a new episode of `f` (0: never in this run).
    pub fn new(rates: [f64; Fault::ALL.len()], client_id: u64) -> Schedule {
        Schedule {
            rates,
            active: Vec::new(),
            stamp: Stamp::new(client_id),
        }
    }

    fn sim(&mut self, cmd: SimCommand) -> CommandSample {
        self.stamp.request(Request::Sim(cmd))
    }

    /// This cycle's injections at cycle `k`.
    pub fn tick(&mut self, k: u64, rng: &mut Rng) -> Injection {
        let mut out = Injection::default();
        let mut bus_changed = false;
        let ended: Vec<Episode> = self
            .active
            .iter()
            .copied()
            .filter(|e| e.until <= k)
            .collect();
        self.active.retain(|e| e.until > k);
        for e in ended {
            bus_changed |= e.fault.is_bus();
            if let Some(cmd) = undo(e.fault, e.axis) {
                let c = self.sim(cmd);
                out.commands.push(c);
            }
        }
        for f in Fault::ALL {
            let rate = self.rates[f.index()];
            if rate == 0.0 || self.active.iter().any(|e| e.fault == f) || !rng.chance(rate) {
                continue;
            }
            let axis = Axis::new(1 + rng.below(NUM_AXES as u64) as u8).expect("1..=6");
            // From a few cycles to about 20 s (5 ms cycles).
            let length = rng.pick(&[2, 20, 200, 1_000, 4_000]);
            let e = Episode {
                fault: f,
                axis,
                until: k + length,
            };
            if let Some(cmd) = start(f, axis, rng) {
                let c = self.sim(cmd);
                out.commands.push(c);
            }
            bus_changed |= f.is_bus();
            out.started.push(f);
            if f != Fault::PowerCycle {
                self.active.push(e);
            }
        }
        if bus_changed {
            out.bus = Some(self.bus_faults(rng));
        }
        out
    }

    /// The bus faults of the bus episodes under way.
    fn bus_faults(&self, rng: &mut Rng) -> BusFaults {
        let mut b = BusFaults::default();
        for e in &self.active {
            let p = rng.pick(&[0.001, 0.01, 0.1]);
            match e.fault {
                Fault::BusLoss => {
                    b.lose_rx = p;
                    b.lose_tx = p;
                }
                Fault::BusCorruption => b.corrupt_rx = p,
                Fault::BusDelay => b.delay_rx = p,
                Fault::BusDuplication => b.duplicate_rx = p,
                Fault::HeartbeatLoss => b.lose_heartbeats_of = Some(e.axis.number()),
                _ => {}
            }
        }
        b
    }

    /// Undo every fault under way (the quiet phase): the `sim` commands that do it.
    pub fn end_all(&mut self) -> Vec<CommandSample> {
        let active = std::mem::take(&mut self.active);
        let mut out = Vec::new();
        for e in active {
            if let Some(cmd) = undo(e.fault, e.axis) {
                out.push(self.sim(cmd));
            }
        }
        out
    }

    /// Faults under way.
    pub fn active(&self) -> impl Iterator<Item = Fault> + '_ {
        self.active.iter().map(|e| e.fault)
    }
}

fn start(f: Fault, axis: Axis, rng: &mut Rng) -> Option<SimCommand> {
    let none = SimCommand::default();
    Some(match f {
        Fault::EmergencyStop => SimCommand {
            emergency_stop: Some(true),
            ..none
        },
        Fault::DriveSilent => SimCommand {
            disconnect_axis: Some(axis),
            ..none
        },
        Fault::Obstacle => SimCommand {
            block_axis: Some(axis),
            ..none
        },
        Fault::Push => {
            let mut tau = [0.0; NUM_AXES];
            tau[axis.index()] = rng.range(-PUSH_MAX_NM, PUSH_MAX_NM);
            SimCommand {
                external_torques_nm: Some(tau),
                ..none
            }
        }
        Fault::PowerCycle => SimCommand {
            power_cycle: true,
            ..none
        },
        _ => return None,
    })
}

fn undo(f: Fault, axis: Axis) -> Option<SimCommand> {
    let none = SimCommand::default();
    Some(match f {
        Fault::EmergencyStop => SimCommand {
            emergency_stop: Some(false),
            ..none
        },
        Fault::DriveSilent => SimCommand {
            reconnect_axis: Some(axis),
            ..none
        },
        Fault::Obstacle => SimCommand {
            unblock_axis: Some(axis),
            ..none
        },
        Fault::Push => SimCommand {
            external_torques_nm: Some([0.0; NUM_AXES]),
            ..none
        },
        _ => return None,
    })
}
