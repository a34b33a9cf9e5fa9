//! The system under test, composed as the real-time process composes it, in virtual time:
//! command intake ([`Intake`]: stops first, then round robin) and rt-core's [`SimCycle`] (the
//! cycle, the controller with its ownership rules and the CANopen master, with the
//! simulator's edge for `sim` fault injection) over the simulated robot behind a
//! [`FaultyBus`].
//!
//! [`World::step`] is one cycle of the real-time loop, the work [`mcm_rt_core::edge::Edge`]
//! does minus the IPC: the commands that arrived go into the backlog, the intake chooses this
//! cycle's, [`SimCycle::run`] runs it. It counts what that work allocates (the global allocator
//! must be [`mcm_shared::alloc_count::CountingAlloc`] for the count to see anything).

use crate::faults::Fault;
use crate::faulty_bus::{BusFaults, FaultyBus};
use crate::rng::Rng;
use crate::script::{Event, Input};
use crate::under_way::UnderWay;
use mcm_rt_core::intake::Intake;
use mcm_rt_core::sim_edge::SimCycle;
use mcm_shared::alloc_count;
use mcm_shared::config::RobotConfig;
use mcm_shared::sample::{CommandSample, Reply, StateSample};
use mcm_shared::service::COMMANDS_PER_CYCLE;
use mcm_sim::SimBus;
use std::collections::VecDeque;

/// The real-time process over the simulated robot, in virtual time.
pub struct World {
    robot: SimCycle<FaultyBus>,
    intake: Intake,
    /// Commands sent but not yet in the backlog (iceoryx2's queue, when the backlog is full).
    queued: VecDeque<CommandSample>,
    period_ns: u64,
    k: u64,
    /// Allocations counted inside the cycle's work so far.
    pub allocations: u64,
    /// The thread's CPU time of the last cycle's work [ns].
    pub last_cpu_ns: u64,
    /// Every input so far, in order (the run's script).
    events: Vec<Event>,
    /// The faults under way, from the inputs ([`UnderWay`]); the bus faults set; and the
    /// faults of the last step.
    under_way: UnderWay,
    bus_faults: BusFaults,
    faults: Vec<Fault>,
    /// The commands the last cycle served, in the order it served them.
    served: [CommandSample; COMMANDS_PER_CYCLE],
    served_len: usize,
}

impl World {
    /// The robot at power-up, under `cfg`; `rng` drives the bus faults.
    pub fn new(cfg: &RobotConfig, rng: Rng) -> World {
        let bus = FaultyBus::new(SimBus::new(cfg), rng);
        let robot = SimCycle::over(cfg, bus, |b| b.sim_mut())
            .expect("the configuration passes the master's checks");
        World {
            robot,
            intake: Intake::new(),
            queued: VecDeque::new(),
            period_ns: cfg.cycle_period_ns(),
            k: 0,
            allocations: 0,
            last_cpu_ns: 0,
            events: Vec::new(),
            under_way: UnderWay::default(),
            bus_faults: BusFaults::default(),
            faults: Vec::new(),
            served: [CommandSample::default(); COMMANDS_PER_CYCLE],
            served_len: 0,
        }
    }

    /// Plant `bug` in the controller (before the first cycle).
    pub fn plant(&mut self, bug: mcm_rt_core::controller::planted::PlantedBug) {
        self.robot.controller_mut().plant(bug);
    }

    /// Cycles run so far.
    pub fn cycle_index(&self) -> u64 {
        self.k
    }

    /// A command arrives (taken into the backlog at the next cycle, as iceoryx2 delivers).
    pub fn send(&mut self, c: CommandSample) {
        self.under_way.sent(&c);
        self.events.push(Event {
            cycle: self.k,
            input: Input::Command(c),
        });
        self.queued.push_back(c);
    }

    /// The bus faults from this cycle on.
    pub fn set_bus_faults(&mut self, b: BusFaults) {
        self.bus_faults = b;
        self.events.push(Event {
            cycle: self.k,
            input: Input::Bus(b),
        });
        self.robot.bus_mut().faults = b;
    }

    /// The faults under way in the last step (derived from the inputs, [`UnderWay`]).
    pub fn faults(&self) -> &[Fault] {
        &self.faults
    }

    /// The inputs so far, handed over.
    pub fn take_events(&mut self) -> Vec<Event> {
        std::mem::take(&mut self.events)
    }

    /// One cycle: the arrived commands into the backlog, this cycle's chosen, the cycle run.
    pub fn step(&mut self) {
        let free = self.intake.free();
        let n = free.len().min(self.queued.len());
        for (slot, c) in free.iter_mut().zip(self.queued.drain(..n)) {
            *slot = c;
        }
        let now_ns = self.k * self.period_ns;
        let (robot, intake) = (&mut self.robot, &mut self.intake);
        let (served, served_len) = (&mut self.served, &mut self.served_len);
        self.faults.clear();
        self.under_way.faults(&self.bus_faults, &mut self.faults);
        let started = thread_cpu_ns();
        let ((), counts) = alloc_count::count(|| {
            intake.received(n);
            let commands = intake.next_cycle();
            *served_len = commands.len().min(COMMANDS_PER_CYCLE);
            served[..*served_len].copy_from_slice(&commands[..*served_len]);
            robot.run(now_ns, commands);
        });
        self.last_cpu_ns = thread_cpu_ns().saturating_sub(started);
        self.allocations += counts.allocations;
        self.k += 1;
        self.under_way.answered(self.robot.replies());
    }

    pub fn state(&self) -> &StateSample {
        self.robot.state()
    }

    /// The commands the last cycle served, in the order it served them (answered in that
    /// cycle or, a `calibrate`, when its calibration ends).
    pub fn served(&self) -> &[CommandSample] {
        &self.served[..self.served_len]
    }

    /// The replies of the last cycle.
    pub fn replies(&self) -> &[Reply] {
        self.robot.replies()
    }

    pub fn bus(&mut self) -> &mut FaultyBus {
        self.robot.bus_mut()
    }

    /// Commands sent and not yet served.
    pub fn waiting(&self) -> usize {
        self.queued.len() + self.intake.waiting()
    }
}

/// The calling thread's CPU time [ns] (`CLOCK_THREAD_CPUTIME_ID`: not advanced while the
/// thread is preempted, so that a busy machine does not fail the work budget).
fn thread_cpu_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec for the duration of the call.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc != 0 {
        return 0;
    }
    u64::try_from(ts.tv_sec).unwrap_or(0) * 1_000_000_000 + u64::try_from(ts.tv_nsec).unwrap_or(0)
}
