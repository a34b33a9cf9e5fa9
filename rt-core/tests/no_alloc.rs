//! The whole cycle allocates nothing, and the whole robot is deterministic.
//!
//! A counting global allocator ([`mcm_shared::alloc_count`]) counts the allocations (and
//! bytes) made on the test thread while [`SimCycle::run`] (the cycle with the simulator's
//! edge, as the runner runs it) runs the controller, the CANopen master, the six simulated
//! drives and the arm physics in virtual time, with `status`, `hold`, `info` and `sim`
//! commands mixed in. The counters are per thread, so the test harness's own threads cannot
//! disturb the figure.
//!
//! [`every_mode`] drives the runner's edge ([`mcm_rt_core::edge::Edge::cycle`], with real
//! iceoryx2 services) through every mode and counts the same way.
//!
//! The last part runs the same scenario twice and compares every published state sample:
//! the same inputs must give the same outputs, bit for bit.

use mcm_rt_core::sim_edge::SimCycle;
use mcm_shared::alloc_count::{self, CountingAlloc};
use mcm_shared::command::{Request, SetTool, SimCommand};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode};
use mcm_shared::sample::{CommandSample, StateSample};
use mcm_shared::tool::Tool;
use mcm_sim::SimBus;

mod common;
#[path = "no_alloc/every_mode.rs"]
mod every_mode;

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

/// Counts the allocations (and bytes) made on this thread inside [`Meter::measure`]. The
/// counters are per thread: tests measuring in parallel do not disturb each other.
#[derive(Debug, Default)]
struct Meter {
    allocs: u64,
    bytes: u64,
}

impl Meter {
    fn new() -> Meter {
        Meter::default()
    }

    /// Run `f`, counting what it allocates on this thread.
    fn measure<R>(&mut self, f: impl FnOnce() -> R) -> R {
        let (r, counts) = alloc_count::count(f);
        self.allocs += counts.allocations;
        self.bytes += counts.bytes;
        r
    }
}

/// Allocations and bytes counted on this thread while `f` ran.
fn count_allocations(f: impl FnOnce()) -> (u64, u64) {
    let mut meter = Meter::new();
    meter.measure(f);
    (meter.allocs, meter.bytes)
}

/// Longest the drives may take to boot, and `hold` to enable them (virtual time).
const BOOT_CYCLES: u64 = 2_000;
const CLIENT: u64 = 1;

fn command(kind: CommandKind, request_id: u64) -> CommandSample {
    CommandSample {
        client_id: CLIENT,
        request_id,
        kind: kind.to_wire(),
        ..CommandSample::default()
    }
}

/// A `sim` command setting the external torques (a hand pushing on the joints) [Nm].
fn external_torques(request_id: u64, torques: [f64; 6]) -> CommandSample {
    let mut c = Request::Sim(SimCommand {
        external_torques_nm: Some(torques),
        ..SimCommand::default()
    })
    .encode();
    (c.client_id, c.request_id) = (CLIENT, request_id);
    c
}

/// A `set_tool` command.
fn set_tool(request_id: u64, tool: Tool) -> CommandSample {
    let mut c = Request::SetTool(SetTool { tool }).encode();
    (c.client_id, c.request_id) = (CLIENT, request_id);
    c
}

/// The simulated robot in virtual time, with a command counter.
struct Robot {
    cycle: SimCycle,
    period_ns: u64,
    k: u64,
    next_request: u64,
    /// The tools `set_tool` alternates: the configured one, and 1 kg more 5 cm to the side.
    tools: [Tool; 2],
}

impl Robot {
    fn new() -> Robot {
        let cfg = RobotConfig::prob2_default();
        let cycle = SimCycle::new(&cfg, SimBus::new(&cfg)).expect("the P-Rob2 config is valid");
        let configured = cfg.arm.tool.active();
        let heavier = Tool::new(
            configured.tcp,
            configured.mass + 1.0,
            [0.05, 0.0, 0.08],
            None,
        )
        .expect("a valid tool");
        Robot {
            cycle,
            period_ns: cfg.cycle_period_ns(),
            k: 0,
            next_request: 1,
            tools: [configured, heavier],
        }
    }

    fn request_id(&mut self) -> u64 {
        let id = self.next_request;
        self.next_request += 1;
        id
    }

    fn run(&mut self, commands: &[CommandSample]) -> &StateSample {
        self.cycle.run(self.k * self.period_ns, commands);
        self.k += 1;
        self.cycle.state()
    }

    /// Run until `done` holds; panics after `max` cycles.
    fn run_until(&mut self, what: &str, max: u64, done: impl Fn(&SimCycle) -> bool) {
        for _ in 0..max {
            if done(&self.cycle) {
                return;
            }
            self.run(&[]);
        }
        panic!("{what} not reached within {max} cycles");
    }

    /// Boot the drives, send `hold`, wait for HOLD, warm up `warmup` cycles.
    fn enter_hold(&mut self, warmup: u64) {
        self.run_until("all drives online", BOOT_CYCLES, |c| {
            c.controller().feedback().iter().all(|f| f.online)
        });
        let hold = command(CommandKind::Hold, self.request_id());
        self.run(&[hold]);
        self.run_until("mode HOLD", BOOT_CYCLES, |c| {
            c.state().mode == Mode::Hold.to_wire()
        });
        for _ in 0..warmup {
            self.run(&[]);
        }
    }

    /// The commands of cycle `i` of the measured scenario: status, hold, info and `set_tool`
    /// (a heavier tool and back) every few cycles, and once a push on the joints (and its
    /// release) through `sim`.
    fn scenario_commands(&mut self, i: u64, push: [f64; 6], out: &mut [CommandSample; 4]) -> usize {
        let mut kinds = [None; 4];
        let mut n = 0;
        for (every, kind) in [
            (5, CommandKind::Status),
            (7, CommandKind::Hold),
            (11, CommandKind::Info),
        ] {
            if i.is_multiple_of(every) {
                kinds[n] = Some(kind);
                n += 1;
            }
        }
        for (slot, kind) in out.iter_mut().zip(kinds.iter().flatten()) {
            *slot = command(*kind, self.request_id());
        }
        if i.is_multiple_of(13) {
            let tool = self.tools[((i / 13) % 2) as usize];
            out[n] = set_tool(self.request_id(), tool);
            n += 1;
        }
        // A hand pushes on the joints for 1000 cycles (5 s), then lets go.
        let torques = match i {
            500 => Some(push),
            1500 => Some([0.0; 6]),
            _ => None,
        };
        if let Some(t) = torques {
            out[n] = external_torques(self.request_id(), t);
            n += 1;
        }
        n
    }
}

const MEASURED_CYCLES: u64 = 2_000;
const PUSH: [f64; 6] = [0.0, 5.0, -3.0, 0.0, 1.0, 0.0];

#[test]
fn the_whole_cycle_allocates_nothing() {
    let mut robot = Robot::new();
    robot.enter_hold(300);
    let replies_before = robot.cycle.state().reply_head;
    let mut commands = [CommandSample::default(); 4];
    let mut last_mode = 0;
    let (allocs, bytes) = count_allocations(|| {
        for i in 0..MEASURED_CYCLES {
            let n = robot.scenario_commands(i, PUSH, &mut commands);
            last_mode = robot.run(&commands[..n]).mode;
        }
    });
    let state = robot.cycle.state();
    // The scenario did what it says: commands were answered, the arm is still held.
    assert!(
        state.reply_head - replies_before > 800,
        "the commands were served: {} replies",
        state.reply_head - replies_before
    );
    assert_eq!(last_mode, Mode::Hold.to_wire(), "still holding");
    // The last `set_tool` (cycle 1989, the 153rd: the heavier tool) was taken.
    assert_eq!(robot.cycle.controller().tool(), &robot.tools[1]);
    assert_eq!(
        (allocs, bytes),
        (0, 0),
        "the cycle allocated {allocs} times ({bytes} bytes) in {MEASURED_CYCLES} cycles"
    );
}

#[test]
fn the_counting_allocator_does_count() {
    // Guards the test above against a counter that cannot see anything.
    let (allocs, bytes) = count_allocations(|| {
        let v: Vec<u64> = std::hint::black_box(Vec::with_capacity(16));
        drop(v);
    });
    assert_eq!((allocs, bytes), (1, 128));
}

/// The published samples of the whole scenario: boot, hold, warm-up, commands, a push.
fn scenario_states(push: [f64; 6]) -> Vec<StateSample> {
    let mut robot = Robot::new();
    let mut states = Vec::new();
    let mut commands = [CommandSample::default(); 4];
    for _ in 0..BOOT_CYCLES {
        if robot.cycle.controller().feedback().iter().all(|f| f.online) {
            break;
        }
        states.push(*robot.run(&[]));
    }
    let hold = command(CommandKind::Hold, robot.request_id());
    states.push(*robot.run(&[hold]));
    for i in 0..MEASURED_CYCLES {
        let n = robot.scenario_commands(i, push, &mut commands);
        states.push(*robot.run(&commands[..n]));
    }
    assert_eq!(
        states.last().unwrap().mode,
        Mode::Hold.to_wire(),
        "the scenario ends in HOLD"
    );
    states
}

#[test]
fn the_same_inputs_give_the_same_outputs() {
    let a = scenario_states(PUSH);
    let b = scenario_states(PUSH);
    assert_eq!(a.len(), b.len(), "both runs took as many cycles to boot");
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        assert_eq!(x.seq, y.seq, "seq of cycle {k}");
        assert_eq!(x.position, y.position, "positions of cycle {k}");
        assert_eq!(x.current, y.current, "currents of cycle {k}");
        assert_eq!(
            x.sim_true_position, y.sim_true_position,
            "true positions of cycle {k}"
        );
        assert_eq!(x, y, "state sample of cycle {k}");
    }
    // The comparison can see a difference: another push gives another trajectory.
    let c = scenario_states([0.0, -5.0, 3.0, 0.0, -1.0, 0.0]);
    assert!(
        a.iter()
            .zip(&c)
            .any(|(x, y)| x.sim_true_position != y.sim_true_position),
        "a different input must change the outputs"
    );
}
