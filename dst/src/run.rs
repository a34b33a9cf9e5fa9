//! One run: a seed's world, clients and faults for a chaos phase, then a quiet phase (faults
//! off, clients gone) in which a last client must bring the arm back to a calibrated HOLD that
//! it can use; every cycle checked ([`Checker`]) and hashed (replay and determinism).

use crate::clients::{Action, Client, FIRST_CLIENT_ID, Limits};
use crate::driver::Driver;
use crate::faults::{Fault, Schedule};
use crate::faulty_bus::{BusFaultCounts, BusFaults};
use crate::hash::RunHash;
use crate::invariants::{Checker, Violation, Work};
use crate::rate::Rate;
use crate::rng::Rng;
use crate::script::Script;
use crate::stamp::{Stamp, calibrate_all};
use crate::swarm::Swarm;
use crate::trace::{Trace, mode_name};
use crate::world::World;
use mcm_shared::command::{Pvt, Request};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode};
use mcm_shared::reply::{Outcome, Response};
use mcm_shared::sample::{
    AXIS_CALIBRATED, AXIS_ENABLED, AXIS_I2T_DERATED, CommandSample, Reply, StateSample,
};

/// Client id of the fault injector's `sim` commands.
pub const FAULT_CLIENT: u64 = 1;
/// Client id of the quiet phase's client.
pub const RECOVERY_CLIENT: u64 = 2;

pub use mcm_rt_core::controller::planted::PlantedBug;

/// Every bug `--planted-bug` can plant, with its name on the command line.
pub const PLANTED_BUGS: [(PlantedBug, &str); 2] = [
    (PlantedBug::BrakingCheckOff, "braking"),
    (PlantedBug::QuickStopSoft, "soft-stop"),
];

/// The name of `bug` on the command line (`--planted-bug NAME`).
pub fn planted_name(bug: PlantedBug) -> &'static str {
    PLANTED_BUGS
        .iter()
        .find(|(b, _)| *b == bug)
        .map_or("?", |(_, name)| name)
}

/// What to run.
#[derive(Debug, Clone, Copy)]
pub struct RunOptions {
    pub seed: u64,
    /// Simulated seconds of the chaos phase.
    pub seconds: f64,
    /// Simulated seconds the quiet phase may take at most.
    pub quiet_seconds: f64,
    pub planted: Option<PlantedBug>,
    /// The run's faults are of the first `fault_kinds` of [`Fault::ALL`] ([`Swarm::draw`]).
    pub fault_kinds: usize,
}

impl RunOptions {
    pub fn new(seed: u64, seconds: f64) -> RunOptions {
        RunOptions {
            seed,
            seconds,
            quiet_seconds: 300.0,
            planted: None,
            fault_kinds: Fault::ALL.len(),
        }
    }

    /// A run whose faults are of the first `kinds` fault kinds only, as when a finding was
    /// found (more kinds change a seed's draws).
    pub fn with_fault_kinds(mut self, kinds: usize) -> RunOptions {
        self.fault_kinds = kinds.min(Fault::ALL.len());
        self
    }
}

/// What a run did.
#[derive(Debug, Clone)]
pub struct RunReport {
    pub seed: u64,
    pub swarm: Swarm,
    pub cycles: u64,
    pub simulated_s: f64,
    /// Hash of every cycle's published state and replies: equal for two runs of a seed.
    pub hash: u64,
    /// The hash after each cycle ([`crate::hash::first_divergence`] of two runs).
    pub checkpoints: Vec<u64>,
    pub violation: Option<Violation>,
    pub modes_reached: [u64; Mode::ALL.len()],
    pub faults_started: [u64; Fault::ALL.len()],
    /// Faults started while the mode was CALIBRATION, and while an axis was braking in ERROR.
    pub faults_in_calibration: u64,
    pub faults_while_braking: u64,
    /// Answers OK, refused, failed.
    pub answers: [u64; 3],
    /// [`Checker::max_overrun_deg`].
    pub max_overrun_deg: f64,
    /// [`Checker::max_work_ns`] (not part of the replay: CPU time is not deterministic).
    pub max_work_ns: u64,
    pub bus: BusFaultCounts,
    /// Cycles the quiet phase took to a calibrated HOLD.
    pub recovery_cycles: Option<u64>,
    /// Every input of the run ([`crate::script`]): what a failing run is replayed and shrunk
    /// from.
    pub script: Script,
}

/// The configuration of a seed's run: the P-Rob2, its encoder offsets and start pose drawn.
pub fn config(rng: &mut Rng) -> RobotConfig {
    let mut cfg = RobotConfig::prob2_default();
    cfg.sim.seed = rng.next_u64();
    for (q, a) in cfg.sim.initial_position_deg.iter_mut().zip(&cfg.axes) {
        *q = rng.range(a.min_deg + 5.0, a.max_deg - 5.0);
    }
    cfg
}

/// The world of `seed`: its swarm options, its configuration, the world under test, and the
/// generator after drawing them (its forks 2 to 4 drive the clients, the faults and the
/// driver). A replay ([`crate::script::replay`]) builds the same world.
pub fn seeded(seed: u64, fault_kinds: usize) -> (Rng, Swarm, RobotConfig, World) {
    let mut rng = Rng::new(seed);
    let swarm = Swarm::draw(&mut rng, fault_kinds);
    let cfg = config(&mut rng);
    let world = World::new(&cfg, rng.fork(1));
    (rng, swarm, cfg, world)
}

/// Run one seed.
pub fn run(opts: &RunOptions) -> RunReport {
    let (mut rng, mut swarm, cfg, mut world) = seeded(opts.seed, opts.fault_kinds);
    if let Some(bug) = opts.planted {
        world.plant(bug);
    }
    let mut client_rng = rng.fork(2);
    let mut fault_rng = rng.fork(3);
    let mut driver_rng = rng.fork(4);
    swarm.draw_roles(&mut driver_rng);
    let limits = Limits::of(&cfg);
    let mut checker = Checker::new(&cfg, world.bus().sim());
    let mut schedule = Schedule::new(swarm.fault_every_s, &cfg, FAULT_CLIENT);
    let mut next_id = FIRST_CLIENT_ID;
    let mut clients: Vec<Client> = (0..swarm.clients)
        .map(|_| {
            next_id += 1;
            Client::new(next_id, &mut client_rng)
        })
        .collect();
    let mut driver = swarm
        .driver
        .then(|| Driver::new(FIRST_CLIENT_ID, &cfg, Rate::of(&cfg), &mut driver_rng));
    let mut report = RunReport {
        seed: opts.seed,
        swarm: swarm.clone(),
        cycles: 0,
        simulated_s: 0.0,
        hash: 0,
        checkpoints: Vec::new(),
        violation: None,
        modes_reached: [0; Mode::ALL.len()],
        faults_started: [0; Fault::ALL.len()],
        faults_in_calibration: 0,
        faults_while_braking: 0,
        answers: [0; 3],
        max_overrun_deg: 0.0,
        max_work_ns: 0,
        bus: BusFaultCounts::default(),
        recovery_cycles: None,
        script: Script {
            seed: opts.seed,
            fault_kinds: opts.fault_kinds,
            planted: opts.planted,
            events: Vec::new(),
        },
    };
    let mut hash = RunHash::default();
    let period_s = cfg.cycle_period_s();
    let chaos_cycles = (opts.seconds / period_s) as u64;
    let tracer = Trace::from_env();

    let step =
        |world: &mut World, checker: &mut Checker, hash: &mut RunHash| -> Result<(), Violation> {
            let before = world.state().mode;
            world.step();
            let k = world.cycle_index();
            let work = Work {
                allocations: std::mem::take(&mut world.allocations),
                cpu_ns: world.last_cpu_ns,
            };
            let s = *world.state();
            tracer.cycle(k, before, &s);
            hash.cycle(&s, world.replies());
            checker.cycle(k, &s, world.replies(), world.served(), work, world.faults())
        };

    let result = (|| -> Result<(), Violation> {
        for _ in 0..chaos_cycles {
            let k = world.cycle_index();
            let s = *world.state();
            let inj = schedule.tick(k, &mut fault_rng);
            for f in &inj.started {
                report.faults_started[f.index()] += 1;
                if s.mode == Mode::Calibration.to_wire() {
                    report.faults_in_calibration += 1;
                }
                if s.mode == Mode::Error.to_wire() && s.velocity.iter().any(|v| v.abs() > 1.0) {
                    report.faults_while_braking += 1;
                }
            }
            for c in inj.commands {
                checker.asked(&c, k);
                world.send(c);
            }
            if let Some(b) = inj.bus {
                world.set_bus_faults(b);
            }
            for client in &mut clients {
                match client.act(&s, &limits, &mut client_rng) {
                    Action::None => {}
                    Action::Send(c) => {
                        checker.asked(&c, k);
                        world.send(c);
                    }
                    Action::Gone(c) => {
                        checker.asked(&c, k);
                        world.send(c);
                        next_id += 1;
                        *client = Client::new(next_id, &mut client_rng);
                    }
                }
            }
            if let Some(c) = driver
                .as_mut()
                .and_then(|d| d.act(&s, &limits, &mut driver_rng))
            {
                checker.asked(&c, k);
                world.send(c);
            }
            step(&mut world, &mut checker, &mut hash)?;
            schedule.answered(world.replies());
        }
        // The quiet phase: faults off, every client gone, the recovery client.
        let k = world.cycle_index();
        for c in schedule.end_all() {
            checker.asked(&c, k);
            world.send(c);
        }
        world.set_bus_faults(BusFaults::default());
        let gone = clients
            .iter_mut()
            .map(Client::gone)
            .chain(driver.as_mut().map(Driver::gone));
        for c in gone {
            checker.asked(&c, k);
            world.send(c);
        }
        // The faults act (and stay under way for the checker) until their undoing is answered.
        while schedule.undoing() {
            step(&mut world, &mut checker, &mut hash)?;
            schedule.answered(world.replies());
        }
        let quiet_cycles = (opts.quiet_seconds / period_s) as u64;
        let mut recovery = Recovery::new(Rate::of(&cfg));
        let start = world.cycle_index();
        while world.cycle_index() - start < quiet_cycles {
            let k = world.cycle_index();
            if let Some(c) = recovery.next(world.state()) {
                checker.asked(&c, k);
                world.send(c);
            }
            step(&mut world, &mut checker, &mut hash)?;
            recovery.read(world.state().seq, world.replies());
            if recovery.done && world.waiting() == 0 {
                report.recovery_cycles = Some(world.cycle_index() - start);
                return checker.left_unanswered(world.cycle_index());
            }
        }
        let k = world.cycle_index();
        let s = world.state();
        let unanswered = checker.unanswered();
        Err(Violation {
            cycle: k,
            quiet_phase: true,
            message: format!(
                "the quiet phase did not end in a usable calibrated HOLD within {} s: mode {}, axis flags {:?}, true angles {:?} deg, currents {:?} A, i2t {:?}, recovery at step {:?} (last answer {:?}), {} commands unanswered (oldest: {:?})",
                opts.quiet_seconds,
                mode_name(s.mode),
                s.axis_flags,
                s.sim_true_position.map(|x| (x * 10.0).round() / 10.0),
                s.current.map(|x| (x * 100.0).round() / 100.0),
                s.i2t.map(|x| (x * 100.0).round() / 100.0),
                recovery.stage,
                recovery.last,
                unanswered.len(),
                unanswered.first()
            ),
        })
    })();
    report.violation = result.err();
    report.cycles = world.cycle_index();
    report.simulated_s = report.cycles as f64 * period_s;
    report.hash = hash.value();
    report.checkpoints = hash.checkpoints().to_vec();
    report.modes_reached = checker.modes_reached;
    report.answers = checker.answers;
    report.max_overrun_deg = checker.max_overrun_deg;
    report.max_work_ns = checker.max_work_ns;
    report.bus = world.bus().counts;
    report.script.events = world.take_events();
    report
}

/// Whether `MCM_DST_TRACE` asks for mode changes and the quiet phase's answers on stderr.
fn trace() -> bool {
    Trace::from_env().modes
}

/// The quiet phase's client: `take_control`, `hold` until HOLD, `calibrate` all axes unless
/// they are, then proves the HOLD usable: `pvt` accepted, `hold` accepted.
#[derive(Debug)]
struct Recovery {
    stage: Stage,
    pending: Option<u64>,
    stamp: Stamp,
    last: Option<Outcome>,
    done: bool,
    /// The state's `seq` before which it sends nothing.
    wait_until: u64,
    rate: Rate,
}

/// How long the quiet phase's client waits after a refusal or failure before it tries again
/// from `hold` [s].
const RETRY_AFTER_S: f64 = 1.0;

/// The i2t level below which the quiet phase's client counts the motors cool enough to enable
/// them again in ERROR (the derating ends below 0.9; from 0.5, a motor holding 1.2 times its
/// rated current reaches the derating again after some 15 s, a calibration's time).
const COOL_LEVEL: f64 = 0.5;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Stage {
    Control,
    Hold,
    Calibrate,
    Use,
    Back,
}

impl Recovery {
    fn new(rate: Rate) -> Recovery {
        Recovery {
            stage: Stage::Control,
            pending: None,
            stamp: Stamp::new(RECOVERY_CLIENT),
            last: None,
            done: false,
            wait_until: 0,
            rate,
        }
    }

    fn next(&mut self, s: &StateSample) -> Option<CommandSample> {
        if self.pending.is_some() || self.done || s.seq < self.wait_until {
            return None;
        }
        let calibrated = s.axis_flags.iter().all(|f| f & AXIS_CALIBRATED != 0);
        // In ERROR the MCM powers the arm off while a motor is derated by i2t (the brakes hold
        // it): let the motors cool before `hold` enables them again, as an operator would (a
        // derated motor cannot give a calibration's search current).
        let derated = s.axis_flags.iter().any(|f| f & AXIS_I2T_DERATED != 0);
        let powered_off = s.axis_flags.iter().all(|f| f & AXIS_ENABLED == 0);
        let hot = s.i2t.iter().any(|level| *level > COOL_LEVEL);
        let cooling = derated || (powered_off && hot);
        if s.mode == Mode::Error.to_wire() && cooling && self.stage == Stage::Hold {
            return None;
        }
        let r = match self.stage {
            Stage::Control => Request::TakeControl,
            Stage::Hold => Request::Hold,
            Stage::Calibrate if calibrated && s.mode == Mode::Hold.to_wire() => {
                self.stage = Stage::Use;
                Request::Pvt(Pvt { dt_s: 0.01 })
            }
            Stage::Calibrate => calibrate_all(),
            Stage::Use => Request::Pvt(Pvt { dt_s: 0.01 }),
            Stage::Back => Request::Hold,
        };
        let c = self.stamp.request(r);
        self.pending = Some(c.request_id);
        Some(c)
    }

    /// The replies of the cycle whose state has `seq` (a reply's own `cycle` is stamped when
    /// the edge publishes it, which the virtual-time cycle does not).
    fn read(&mut self, seq: u64, replies: &[Reply]) {
        for r in replies {
            if r.client_id != RECOVERY_CLIENT || Some(r.request_id) != self.pending {
                continue;
            }
            self.pending = None;
            let Ok(resp) = Response::decode(r) else {
                continue;
            };
            let ok = matches!(resp.outcome, Outcome::Done(_));
            if trace() {
                eprintln!(
                    "cycle {}: recovery {:?}: {} -> {:?}",
                    seq, self.stage, resp.kind, resp.outcome
                );
            }
            self.last = Some(resp.outcome);
            let kind = resp.kind;
            self.stage = match (self.stage, ok) {
                (Stage::Control, true) => Stage::Hold,
                (Stage::Hold, true) => Stage::Calibrate,
                (Stage::Calibrate, true) => Stage::Calibrate, // checked again on the state
                (Stage::Use, true) if kind == CommandKind::Pvt => Stage::Back,
                (Stage::Back, true) => {
                    self.done = true;
                    Stage::Back
                }
                // Refused or failed (a drive still booting, a calibration that failed):
                // start again from `hold`, a second later.
                (Stage::Control, false) => Stage::Control,
                (_, false) => {
                    self.wait_until = seq + self.rate.cycles(RETRY_AFTER_S);
                    Stage::Hold
                }
                (s, true) => s,
            };
        }
    }
}
