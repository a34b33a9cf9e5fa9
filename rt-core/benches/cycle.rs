//! Benchmarks of the work done inside the real-time cycle (criterion).
//!
//! ```sh
//! cargo bench -p mcm-rt-core --bench cycle
//! ```
//!
//! - `cycle/run_hold_sim`: one whole cycle in HOLD against the simulated robot as the runner
//!   runs it ([`SimCycle::run`]: the cycle with the simulator's edge): the controller, the
//!   CANopen master, six simulated CiA 402 drives and the arm physics (10 physics sub-steps of
//!   500 µs). On a real arm the simulation is replaced by SocketCAN
//!   system calls, so this is an upper bound of the controller's share.
//! - `cycle/run_joint_move_sim`, `cycle/run_line_sim`: the same whole cycle, calibrated in PVT,
//!   while a joint move (`move_all`) runs, and while a 15 cm `move_linear` line runs (its
//!   reference sampled from the line's plan each cycle); the moves go back and forth, and the
//!   cycles that take a command in and answer it (with the line's planning, which `mcm-rt`
//!   does on its planner thread) are not counted.
//! - `reference/joint_move`, `reference/line`: the one part of those cycles that differs, the
//!   cycle's reference: `JointPlan::advance` of the joint move against `LinePlan::sample` of
//!   the line (one branch of the inverse kinematics, a 6×6 solve), along the same 15 cm.
//! - `cycle/accept_identify_payload_sim`: the cycle that takes `identify_payload` in, which
//!   judges the poses and plans the whole sequence of moves before anything moves (each run
//!   aborted with `hold`, the arm at rest again before the next).
//! - `dynamics/gravity_torques`, `dynamics/forward_dynamics`: the arm model's per-call
//!   functions (RNEA; mass matrix + RNEA + Cholesky solve).
//! - `cartesian/compose`: the TCP's state the cycle adds to the sample once calibrated
//!   ([`Cartesian::compose`]: forward kinematics, Jacobian times the axis velocities, the
//!   conversions), for a moving configuration of the P-Rob2.
//! - `cycle/run_velocity_joint_sim`, `cycle/run_velocity_cartesian_sim`: one whole cycle in
//!   VELOCITY_CONTROL, calibrated, from a pose away from the singularities, the arm moving:
//!   under `set_velocities`, and under `set_cartesian_velocity` (the TCP's velocity through
//!   the Jacobian every cycle, `controller/velocity/twist.rs`); both ramped by the same ramp,
//!   the direction reversed every 400 cycles (2 s) so that the arm keeps moving.
//! - `cartesian/velocity_target`: the work the cycle adds under `set_cartesian_velocity` alone
//!   (`controller::velocity::twist::joint_target`: the twist in the tool frame turned into the
//!   base frame, the Jacobian, the singularity measures twice, the solve, the shares of the
//!   limits), at the configuration of the VELOCITY_CONTROL benchmarks.
//! - `canopen/master_hold`: the CANopen master alone, `handle_frame` for one cycle's received
//!   frames plus `cycle` (RPDOs, SYNC), replaying frames recorded from the simulated drives in
//!   HOLD.
//!
//! Results and the machine they were measured on: `docs/performance.md`.

use criterion::{Criterion, criterion_group, criterion_main};
use mcm_bus::{Bus, Frame};
use mcm_dynamics::ArmModel;
use mcm_rt_core::canopen::{DriveRequest, FrameBuf, Master};
use mcm_rt_core::cartesian::Cartesian;
use mcm_rt_core::controller::velocity::ramp::RampLimits;
use mcm_rt_core::controller::velocity::ramp_limits;
use mcm_rt_core::controller::velocity::twist::{Twist, joint_target};
use mcm_rt_core::line_planner::joint_limits;
use mcm_rt_core::params::JointParams;
use mcm_rt_core::safety::SafetyParams;
use mcm_rt_core::sim_edge::SimCycle;
use mcm_rt_core::trajectory::{JointPlan, MovePlan};
use mcm_shared::command::{
    Calibrate, CartesianFrame, IdentifyPayload, MoveAll, MoveLinear, Pvt, Request,
    SetCartesianVelocity, SetVelocities, VelocityControl,
};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode};
use mcm_shared::sample::{CommandSample, STATE_ALL_CALIBRATED, STATE_CARTESIAN, StateSample};
use mcm_sim::SimBus;
use std::hint::black_box;
use std::time::{Duration, Instant};

/// Longest the drives may take to boot and enable (virtual time).
const BOOT_CYCLES: u64 = 2_000;

fn cycle_in_hold(c: &mut Criterion) {
    let cfg = RobotConfig::prob2_default();
    let period = cfg.cycle_period_ns();
    let mut cycle = SimCycle::new(&cfg, SimBus::new(&cfg)).unwrap();
    let mut k = 0u64;
    let mut step = |cycle: &mut SimCycle, commands: &[CommandSample]| {
        cycle.run(k * period, commands);
        k += 1;
        k
    };
    while !cycle.controller().feedback().iter().all(|f| f.online) {
        assert!(
            step(&mut cycle, &[]) < BOOT_CYCLES,
            "the drives did not come online"
        );
    }
    let hold = CommandSample {
        client_id: 1,
        request_id: 1,
        kind: CommandKind::Hold.to_wire(),
        ..CommandSample::default()
    };
    step(&mut cycle, &[hold]);
    while cycle.controller().mode() != Mode::Hold {
        assert!(step(&mut cycle, &[]) < 2 * BOOT_CYCLES, "HOLD not reached");
    }
    c.bench_function("cycle/run_hold_sim", |b| {
        b.iter(|| {
            cycle.run(k * period, black_box(&[]));
            k += 1;
        })
    });
    assert_eq!(cycle.controller().mode(), Mode::Hold, "held throughout");
}

/// Cycles between two reversals of the velocity in the VELOCITY_CONTROL benchmarks.
const REVERSE_CYCLES: u64 = 400;

/// The simulated robot stepped cycle by cycle, with the commands of one client.
struct Driver {
    cycle: SimCycle,
    k: u64,
    period: u64,
    id: u64,
}

impl Driver {
    /// One cycle, with `req` if given.
    fn send(&mut self, req: Option<Request>) {
        let mut s = req.map(|r| r.encode());
        if let Some(s) = s.as_mut() {
            self.id += 1;
            (s.client_id, s.request_id) = (1, self.id);
        }
        self.cycle.run(self.k * self.period, s.as_slice());
        self.k += 1;
    }

    /// Cycles until `done`.
    fn until(&mut self, what: &str, done: impl Fn(&SimCycle) -> bool) {
        let limit = self.k + 40 * BOOT_CYCLES;
        while !done(&self.cycle) {
            assert!(self.k < limit, "{what} not reached");
            self.send(None);
        }
    }
}

/// A calibrated simulated robot in VELOCITY_CONTROL (no timeout) at rest at a pose away from
/// the singularities.
fn in_velocity_control() -> Driver {
    let mut d = robot_in_pvt([17.0, 29.0, 57.0, 23.0, 46.0, -17.0]);
    d.send(Some(Request::Hold));
    d.send(Some(Request::VelocityControl(VelocityControl {
        timeout_s: None,
    })));
    assert_eq!(d.cycle.controller().mode(), Mode::VelocityControl);
    d
}

/// The VELOCITY_CONTROL benchmark `name`: `request(sign)` every [`REVERSE_CYCLES`] cycles.
fn velocity_bench(c: &mut Criterion, name: &str, request: impl Fn(f64) -> Request) {
    let mut d = in_velocity_control();
    let start = d.k;
    c.bench_function(name, |b| {
        b.iter(|| {
            let n = d.k - start;
            let req = n.is_multiple_of(REVERSE_CYCLES).then(|| {
                let sign = if (n / REVERSE_CYCLES).is_multiple_of(2) {
                    1.0
                } else {
                    -1.0
                };
                request(sign)
            });
            d.send(black_box(req));
        })
    });
    assert_eq!(
        d.cycle.controller().mode(),
        Mode::VelocityControl,
        "{name}: no trip, no timeout"
    );
}

fn cycle_in_velocity_control(c: &mut Criterion) {
    // About the same joint speeds in both: 0.05 m/s of the TCP at this pose is a few deg/s.
    velocity_bench(c, "cycle/run_velocity_joint_sim", |sign| {
        Request::SetVelocities(SetVelocities {
            velocities_deg_s: [3.0 * sign, -3.0 * sign, 4.0 * sign, 0.0, 2.0 * sign, 0.0],
        })
    });
    velocity_bench(c, "cycle/run_velocity_cartesian_sim", |sign| {
        Request::SetCartesianVelocity(SetCartesianVelocity {
            linear_m_s: [0.05 * sign, 0.0, 0.0],
            angular_deg_s: [0.0; 3],
            frame: CartesianFrame::Base,
        })
    });
}

/// A calibrated robot in PVT at rest at `at` [deg].
fn robot_in_pvt(at: [f64; 6]) -> Driver {
    let cfg = RobotConfig::prob2_default();
    let mut d = Driver {
        cycle: SimCycle::new(&cfg, SimBus::new(&cfg)).unwrap(),
        k: 0,
        period: cfg.cycle_period_ns(),
        id: 0,
    };
    d.until("drives online", |c| {
        c.controller().feedback().iter().all(|f| f.online)
    });
    d.send(Some(Request::Calibrate(Calibrate::default())));
    d.until("calibrated in HOLD", |c| {
        c.controller().mode() == Mode::Hold && c.state().flags & STATE_ALL_CALIBRATED != 0
    });
    d.send(Some(Request::Pvt(Pvt { dt_s: 0.01 })));
    d.send(Some(Request::MoveAll(MoveAll {
        targets_deg: at,
        velocity_factor: 1.0,
    })));
    d.until("at rest at the start", |c| {
        let s = c.state();
        s.position
            .iter()
            .zip(&at)
            .all(|(p, q)| (p - q).abs() < 1e-9)
            && s.velocity.iter().all(|v| *v == 0.0)
    });
    assert_eq!(d.cycle.controller().mode(), Mode::Pvt);
    d
}

/// Time whole cycles while the motions `there` and `back` run in turn; the cycle that takes
/// each in and the next (its answer: for a line, its planning) are not counted.
fn cycle_while(c: &mut Criterion, name: &str, start: [f64; 6], there: Request, back: Request) {
    let mut d = robot_in_pvt(start);
    let mut next = [there, back].into_iter().cycle();
    let mut since_command = 0u64;
    c.bench_function(name, |b| {
        b.iter_custom(|iters| {
            let mut timed = Duration::ZERO;
            let mut counted = 0;
            while counted < iters {
                let at_rest = d.cycle.state().velocity.iter().all(|v| *v == 0.0);
                if since_command > 2 && at_rest {
                    d.send(next.next());
                    since_command = 0;
                    continue;
                }
                let t0 = Instant::now();
                d.cycle.run(d.k * d.period, black_box(&[]));
                let dt = t0.elapsed();
                d.k += 1;
                since_command += 1;
                if since_command > 1 {
                    timed += dt;
                    counted += 1;
                }
            }
            timed
        })
    });
    assert_eq!(d.cycle.controller().mode(), Mode::Pvt, "moved throughout");
}

/// The cycle that takes `identify_payload` in: it judges the poses and plans the whole
/// sequence before anything moves (17 joint moves, the estimator's regressor at four poses);
/// each accepted run is aborted with `hold` and the arm left to come to rest before the next.
fn cycle_accepting_identify_payload(c: &mut Criterion) {
    let mut d = robot_in_pvt([20.0, 30.0, 60.0, -40.0, 50.0, 10.0]);
    d.send(Some(Request::Hold));
    let at_rest = |c: &SimCycle| {
        c.controller().mode() == Mode::Hold && c.state().velocity.iter().all(|v| *v == 0.0)
    };
    d.until("at rest in HOLD", at_rest);
    c.bench_function("cycle/accept_identify_payload_sim", |b| {
        b.iter_custom(|iters| {
            let mut timed = Duration::ZERO;
            for _ in 0..iters {
                let t0 = Instant::now();
                d.send(black_box(Some(Request::IdentifyPayload(IdentifyPayload {
                    apply: false,
                }))));
                timed += t0.elapsed();
                // Accepted: answered only when the procedure ends (a refusal answers at once).
                assert!(d.cycle.replies().is_empty(), "{:?}", d.cycle.replies());
                d.send(Some(Request::Hold));
                d.until("at rest in HOLD again", at_rest);
            }
            timed
        })
    });
}

/// The one part of a cycle in which a line differs from a joint move: the reference of the
/// cycle, `LinePlan::sample` against `JointPlan::advance`, along the same 15 cm (the ends of
/// [`cycle_moving`]), time stepping by the cycle period and starting over at the end.
fn reference_step(c: &mut Criterion) {
    let cfg = RobotConfig::prob2_default();
    let p = JointParams::from_config(&cfg);
    let dt = cfg.cycle_period_ns() as f64 * 1e-9;
    let (start, b, target) = line_ends();
    let start = start.map(f64::to_radians);
    let move_plan = MovePlan::plan(start, target.map(f64::to_radians), &p.limits, 0.5).unwrap();
    let joint = JointPlan::from_move(&move_plan).unwrap();
    let mut running = joint;
    c.bench_function("reference/joint_move", |bench| {
        bench.iter(|| {
            if running.finished() {
                running = joint;
            }
            black_box(running.advance(dt))
        })
    });
    let kin = mcm_kinematics::Kinematics::from_config(&cfg).unwrap();
    let line = mcm_kinematics::LinePlan::plan(
        &kin,
        &joint_limits(&p),
        &start,
        &mcm_kinematics::LineTarget {
            position: b,
            orientation: None,
            velocity: Some(0.25),
            acceleration: None,
        },
    )
    .unwrap();
    let mut t = 0.0;
    c.bench_function("reference/line", |bench| {
        bench.iter(|| {
            t = if t > line.duration() { 0.0 } else { t + dt };
            black_box(line.sample(black_box(t)))
        })
    });
}

/// The ends of the benchmarks' 15 cm line: the start configuration [deg], the target TCP
/// position, and the start's branch of the inverse kinematics there [deg].
fn line_ends() -> ([f64; 6], nalgebra::Vector3<f64>, [f64; 6]) {
    let start = [20.0, 30.0, 60.0, -40.0, 50.0, 10.0];
    let kin = mcm_kinematics::Kinematics::from_config(&RobotConfig::prob2_default()).unwrap();
    let rad = start.map(f64::to_radians);
    let b = kin.tcp_pose(&rad).translation.vector + nalgebra::Vector3::new(0.0, 0.134, -0.067);
    let target = kin
        .inverse_branch(
            &nalgebra::Isometry3::from_parts(b.into(), kin.tcp_pose(&rad).rotation),
            kin.branch(&rad),
            &rad,
        )
        .unwrap()
        .map(f64::to_degrees);
    (start, b, target)
}

/// A joint move and a 15 cm line between the same two configurations of the P-Rob2.
fn cycle_moving(c: &mut Criterion) {
    let (start, b, target) = line_ends();
    let kin = mcm_kinematics::Kinematics::from_config(&RobotConfig::prob2_default()).unwrap();
    let a = kin.tcp_pose(&start.map(f64::to_radians)).translation.vector;
    let line = |p: nalgebra::Vector3<f64>| {
        Request::MoveLinear(MoveLinear {
            position: [p.x, p.y, p.z],
            orientation: None,
            velocity: Some(0.25),
            acceleration: None,
        })
    };
    let joint = |targets_deg| {
        Request::MoveAll(MoveAll {
            targets_deg,
            velocity_factor: 0.5,
        })
    };
    cycle_while(
        c,
        "cycle/run_joint_move_sim",
        start,
        joint(target),
        joint(start),
    );
    cycle_while(c, "cycle/run_line_sim", start, line(b), line(a));
}

fn dynamics(c: &mut Criterion) {
    let cfg = RobotConfig::prob2_default();
    let model = ArmModel::from_config(&cfg);
    let q = [0.3, 1.2, -0.7, 0.4, 0.9, -0.2];
    let qd = [0.5, -0.3, 0.8, -1.0, 0.2, 1.5];
    let tau = [1.0, -40.0, -15.0, 0.5, -3.0, 0.1];
    c.bench_function("dynamics/gravity_torques", |b| {
        b.iter(|| model.gravity_torques(black_box(&q)))
    });
    c.bench_function("dynamics/forward_dynamics", |b| {
        b.iter(|| model.forward_dynamics(black_box(&q), black_box(&qd), black_box(&tau)))
    });
}

/// Frames received per cycle over this many cycles of HOLD are replayed (1 s: several
/// heartbeats of every drive).
const RECORDED_CYCLES: usize = 200;

/// A master brought to HOLD against the simulated drives, and the frames the drives sent in
/// the following [`RECORDED_CYCLES`] cycles (one list per cycle).
fn master_in_hold(cfg: &RobotConfig) -> (Master, u64, [DriveRequest; 6], Vec<Vec<Frame>>) {
    let period = cfg.cycle_period_ns();
    let max_current: [f64; 6] = core::array::from_fn(|i| cfg.axes[i].max_current_a);
    let mut master = Master::new(cfg).unwrap();
    let mut bus = SimBus::new(cfg);
    let mut out = FrameBuf::new();
    let mut requests = [DriveRequest::Disable; 6];
    let mut recorded = Vec::new();
    let mut holding = false;
    for k in 0..2 * BOOT_CYCLES {
        let now = k * period;
        let mut rx = Vec::new();
        while let Some(f) = bus.recv(0).unwrap() {
            master.handle_frame(now, &f);
            rx.push(f);
        }
        while master.poll_event().is_some() {}
        let fb = *master.feedback();
        if !holding && fb.iter().all(|f| f.online) {
            holding = true;
            master.reset_faults();
            requests = core::array::from_fn(|i| DriveRequest::Position {
                position_rad: fb[i].position_rad,
            });
        }
        if holding && fb.iter().all(|f| f.enabled) {
            recorded.push(rx);
            if recorded.len() == RECORDED_CYCLES {
                return (master, now + period, requests, recorded);
            }
        }
        out.clear();
        master.cycle(now, &requests, &max_current, &mut out);
        for f in out.iter() {
            bus.send(f).unwrap();
        }
    }
    panic!(
        "the drives were not enabled within {} cycles",
        2 * BOOT_CYCLES
    );
}

fn master_alone(c: &mut Criterion) {
    let cfg = RobotConfig::prob2_default();
    let period = cfg.cycle_period_ns();
    let max_current: [f64; 6] = core::array::from_fn(|i| cfg.axes[i].max_current_a);
    let (mut master, mut now, requests, recorded) = master_in_hold(&cfg);
    let mut out = FrameBuf::new();
    let mut k = 0usize;
    c.bench_function("canopen/master_hold", |b| {
        b.iter(|| {
            for f in &recorded[k % RECORDED_CYCLES] {
                master.handle_frame(now, black_box(f));
            }
            while master.poll_event().is_some() {}
            out.clear();
            master.cycle(now, &requests, &max_current, &mut out);
            now += period;
            k += 1;
            black_box(out.len())
        })
    });
    assert!(
        master.feedback().iter().all(|f| f.enabled && f.online),
        "the replayed drives stayed online and enabled"
    );
}

fn cartesian(c: &mut Criterion) {
    let cartesian = Cartesian::from_config(&RobotConfig::prob2_default()).unwrap();
    let mut s = StateSample {
        flags: STATE_ALL_CALIBRATED,
        position: [17.0, 68.0, -40.0, 23.0, 51.0, -11.0],
        velocity: [30.0, -17.0, 45.0, -57.0, 11.0, 86.0],
        ..StateSample::default()
    };
    cartesian.compose(&mut s);
    assert_ne!(s.flags & STATE_CARTESIAN, 0, "composed");
    c.bench_function("cartesian/compose", |b| {
        b.iter(|| cartesian.compose(black_box(&mut s)))
    });
    let cfg = RobotConfig::prob2_default();
    let (p, safety) = (
        JointParams::from_config(&cfg),
        SafetyParams::from_config(&cfg),
    );
    let limits: [RampLimits; 6] = core::array::from_fn(|i| ramp_limits(&p, &safety, i));
    let q = [17.0f64, 29.0, 57.0, 23.0, 46.0, -17.0].map(f64::to_radians);
    let t = Twist {
        linear: [0.05, -0.02, 0.01],
        angular: [0.0, 0.1, -0.1],
        frame: CartesianFrame::Tool,
    };
    let kin = cartesian.kinematics();
    c.bench_function("cartesian/velocity_target", |b| {
        b.iter(|| joint_target(kin, black_box(&q), black_box(&t), &limits))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = cycle_in_hold, cycle_in_velocity_control, cycle_moving,
        cycle_accepting_identify_payload, reference_step, dynamics, cartesian, master_alone
}
criterion_main!(benches);
