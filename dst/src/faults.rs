//! The faults of a run: what the simulated robot can suffer (emergency stop, a drive's cable
//! pulled, an obstacle, a hand pushing, the drives' power switched off and on) through `sim`
//! commands as a client sends them, and bus faults ([`BusFaults`]) set on the faulty bus
//! (frames lost, corrupted, delayed or duplicated, one drive's heartbeats lost, a stuck SYNC,
//! one drive rebooting).
//!
//! Each kind of fault comes in episodes: it starts at a random cycle (any mode, calibration
//! and braking included) and is undone after a random duration. Which kinds a run uses and how
//! often is its [`Swarm`](crate::swarm::Swarm)'s choice.

use crate::faulty_bus::BusFaults;
use crate::rate::Rate;
use crate::rng::Rng;
use crate::stamp::Stamp;
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Axis, Request, SimCommand};
use mcm_shared::config::RobotConfig;
use mcm_shared::sample::{CommandSample, Reply};

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
    /// No SYNC reaches the drives for the episode.
    SyncStuck,
    /// One drive reboots: its supply off for the episode, then it boots as at power-up.
    DriveReboot,
}

impl Fault {
    /// Whether the fault moves the arm or takes it from the controller's hands (a push, an
    /// obstacle, the drives' power cut, a drive gone silent or rebooting: its power stage off),
    /// so that where the arm goes is not the controller's doing while it acts.
    pub fn moves_the_arm(self) -> bool {
        matches!(
            self,
            Fault::Push
                | Fault::Obstacle
                | Fault::PowerCycle
                | Fault::EmergencyStop
                | Fault::DriveSilent
                | Fault::DriveReboot
        )
    }

    pub const ALL: [Fault; 12] = [
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
        Fault::SyncStuck,
        Fault::DriveReboot,
    ];

    /// Its place in [`Fault::ALL`] (the declaration order, checked at compile time below).
    pub fn index(self) -> usize {
        self as usize
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
            Fault::SyncStuck => "sync_stuck",
            Fault::DriveReboot => "drive_reboot",
        }
    }

    /// Set on the faulty bus ([`BusFaults`]) rather than by a `sim` command.
    fn is_bus(self) -> bool {
        self.per_frame()
            || matches!(
                self,
                Fault::HeartbeatLoss | Fault::SyncStuck | Fault::DriveReboot
            )
    }

    /// A bus fault that hits frames at random, with a chance per frame drawn per episode.
    fn per_frame(self) -> bool {
        matches!(
            self,
            Fault::BusLoss | Fault::BusCorruption | Fault::BusDelay | Fault::BusDuplication
        )
    }
}

// `Fault::ALL` lists the kinds in their declaration order, which `Fault::index` relies on.
const _: () = {
    let mut i = 0;
    while i < Fault::ALL.len() {
        assert!(Fault::ALL[i] as usize == i);
        i += 1;
    }
};

/// How long an episode lasts, from a few cycles to 20 s [s].
const EPISODE_S: [f64; 5] = [0.01, 0.1, 1.0, 5.0, 20.0];
/// The chance per frame a bus episode hits a frame with (one drawn per episode).
const BUS_FAULT_CHANCES: [f64; 3] = [0.001, 0.01, 0.1];

/// One fault under way: its kind, the axis it concerns, the cycle it ends, the chance per
/// frame of a bus fault.
#[derive(Debug, Clone, Copy)]
struct Episode {
    fault: Fault,
    axis: Axis,
    until: u64,
    p: f64,
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
    rate: Rate,
    /// The CANopen node id of each axis's drive.
    node_ids: [u8; NUM_AXES],
    active: Vec<Episode>,
    /// Episodes ended whose undoing `sim` command is not answered yet (request id, fault):
    /// until then the fault still acts.
    undoing: Vec<(u64, Fault)>,
    stamp: Stamp,
}

impl Schedule {
    /// `every_s[f.index()]`: mean time between the episodes of `f` [s] (`None`: never in this
    /// run); `client_id`: the injector's, for its `sim` commands.
    pub fn new(
        every_s: [Option<f64>; Fault::ALL.len()],
        cfg: &RobotConfig,
        client_id: u64,
    ) -> Schedule {
        let period_s = cfg.cycle_period_s();
        Schedule {
            rates: every_s.map(|e| e.map_or(0.0, |e| period_s / e)),
            rate: Rate::of(cfg),
            node_ids: core::array::from_fn(|i| cfg.axes[i].node_id),
            active: Vec::new(),
            undoing: Vec::new(),
            stamp: Stamp::new(client_id),
        }
    }

    fn sim(&mut self, cmd: SimCommand) -> CommandSample {
        self.stamp.request(Request::Sim(cmd))
    }

    /// The `sim` command that undoes `e`, if it needs one; the fault counts as under way until
    /// it is answered ([`Schedule::answered`]).
    fn undo(&mut self, e: Episode) -> Option<CommandSample> {
        let c = self.sim(undo(e.fault, e.axis)?);
        self.undoing.push((c.request_id, e.fault));
        Some(c)
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
            out.commands.extend(self.undo(e));
        }
        for f in Fault::ALL {
            let rate = self.rates[f.index()];
            if rate == 0.0 || self.active.iter().any(|e| e.fault == f) || !rng.chance(rate) {
                continue;
            }
            let axis = Axis::new(1 + rng.below(NUM_AXES as u64) as u8).expect("1..=6");
            let length = self.rate.cycles(rng.pick(&EPISODE_S));
            let p = if f.per_frame() {
                rng.pick(&BUS_FAULT_CHANCES)
            } else {
                0.0
            };
            let e = Episode {
                fault: f,
                axis,
                until: k + length,
                p,
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
            out.bus = Some(self.bus_faults());
        }
        out
    }

    /// The bus faults of the bus episodes under way.
    fn bus_faults(&self) -> BusFaults {
        let mut b = BusFaults::default();
        for e in &self.active {
            match e.fault {
                Fault::BusLoss => {
                    b.lose_rx = e.p;
                    b.lose_tx = e.p;
                }
                Fault::BusCorruption => b.corrupt_rx = e.p,
                Fault::BusDelay => b.delay_rx = e.p,
                Fault::BusDuplication => b.duplicate_rx = e.p,
                Fault::HeartbeatLoss => b.lose_heartbeats_of = Some(self.node_ids[e.axis.index()]),
                Fault::SyncStuck => b.sync_stuck = true,
                Fault::DriveReboot => b.rebooting = Some(e.axis.index()),
                _ => {}
            }
        }
        b
    }

    /// Undo every fault under way (the quiet phase): the `sim` commands that do it.
    pub fn end_all(&mut self) -> Vec<CommandSample> {
        let active = std::mem::take(&mut self.active);
        active.into_iter().filter_map(|e| self.undo(e)).collect()
    }

    /// The replies of a cycle: the undoing commands answered end their faults.
    pub fn answered(&mut self, replies: &[Reply]) {
        let me = self.stamp.client_id;
        self.undoing.retain(|(id, _)| {
            !replies
                .iter()
                .any(|r| r.client_id == me && r.request_id == *id)
        });
    }

    /// Whether a fault ended but its undoing is not answered yet.
    pub fn undoing(&self) -> bool {
        !self.undoing.is_empty()
    }

    /// Faults under way, the ones being undone included.
    pub fn active(&self) -> impl Iterator<Item = Fault> + '_ {
        self.active
            .iter()
            .map(|e| e.fault)
            .chain(self.undoing.iter().map(|u| u.1))
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
