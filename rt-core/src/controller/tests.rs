//! Scenario tests of the controller against the simulated robot, in virtual time: the whole
//! robot (controller, CANopen master, simulated drives, physics) stepped cycle by cycle, with
//! the simulator's edge as the runner wires it in ([`SimCycle`]).

use crate::sim_edge::SimCycle;
use mcm_shared::command::{
    Axis, Calibrate, Direction, MoveAll, MoveAxis, Pvt, PvtChunk, PvtPoint, Request, SetTorques,
    SimCommand, TorqueControl, Which,
};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::Mode;
use mcm_shared::reply::{Done, Outcome, Reason, Response};
use mcm_shared::sample::CommandSample;
use mcm_sim::SimBus;

pub(crate) struct Robot {
    pub cycle: SimCycle,
    pub k: u64,
    pub period: u64,
    next_request: u64,
    /// Every reply given so far, oldest first.
    pub replies: Vec<mcm_shared::sample::Reply>,
}

impl Robot {
    pub fn new() -> Robot {
        Self::with_config(&RobotConfig::prob2_default())
    }

    pub fn with_config(cfg: &RobotConfig) -> Robot {
        let mut r = Robot {
            cycle: SimCycle::new(cfg, SimBus::new(cfg)).unwrap(),
            k: 0,
            period: cfg.cycle_period_ns(),
            next_request: 1,
            replies: Vec::new(),
        };
        r.run_until("drives online", 400, |r| {
            r.cycle.controller().feedback().iter().all(|f| f.online)
        });
        r
    }

    pub fn step(&mut self, commands: &[CommandSample]) {
        self.cycle.run(self.k * self.period, commands);
        self.k += 1;
        self.replies.extend_from_slice(self.cycle.replies());
    }

    pub fn run(&mut self, cycles: u64) {
        for _ in 0..cycles {
            self.step(&[]);
        }
    }

    pub fn run_until(&mut self, what: &str, max_cycles: u64, done: impl Fn(&Robot) -> bool) {
        for _ in 0..max_cycles {
            if done(self) {
                return;
            }
            self.step(&[]);
        }
        panic!(
            "{what}: not reached within {max_cycles} cycles; mode {:?}",
            self.mode()
        );
    }

    pub fn mode(&self) -> Mode {
        self.cycle.controller().mode()
    }

    /// Send one request and run until its reply arrives (at most `max_cycles`).
    pub fn command(&mut self, req: Request, max_cycles: u64) -> Response {
        self.command_from(42, req, max_cycles)
    }

    /// Send one request as the client `client_id` and run until its reply arrives.
    pub fn command_from(&mut self, client_id: u64, req: Request, max_cycles: u64) -> Response {
        let mut s = req.encode();
        s.client_id = client_id;
        s.request_id = self.next_request;
        self.next_request += 1;
        let id = s.request_id;
        self.step(&[s]);
        for _ in 0..max_cycles {
            if let Some(r) = self.cycle.replies().iter().find(|r| r.request_id == id) {
                return Response::decode(r).expect("a well-formed reply");
            }
            self.step(&[]);
        }
        panic!("no reply to {req:?} within {max_cycles} cycles");
    }

    /// Send one request and expect it done; what it answered.
    pub fn ok(&mut self, req: Request, max_cycles: u64) -> Done {
        let r = self.command(req, max_cycles);
        match r.outcome {
            Outcome::Done(done) => done,
            other => panic!("{:?} failed: {other:?}", r.kind),
        }
    }

    /// Send one request and expect it refused; why.
    pub fn refused(&mut self, req: Request, max_cycles: u64) -> Reason {
        let r = self.command(req, max_cycles);
        match r.outcome {
            Outcome::Refused(reason) => reason,
            other => panic!("{:?} was not refused: {other:?}", r.kind),
        }
    }

    /// Measured joint positions [deg], as reported.
    pub fn measured(&self) -> [f64; 6] {
        self.cycle.state().measured_position
    }

    /// The simulation's true joint angles [deg].
    pub fn truth(&self) -> [f64; 6] {
        self.cycle.state().sim_true_position
    }

    /// A calibrated robot in HOLD.
    pub fn calibrated() -> Robot {
        let mut r = Robot::new();
        r.calibrate_all();
        r
    }

    /// The fastest true joint speed [deg/s].
    pub fn fastest_true_speed(&self) -> f64 {
        self.cycle
            .state()
            .sim_true_velocity
            .iter()
            .fold(0.0, |m: f64, v| m.max(v.abs()))
    }

    /// Every true joint slower than 0.05 deg/s.
    pub fn at_rest(&self) -> bool {
        self.cycle
            .state()
            .sim_true_velocity
            .iter()
            .all(|v| v.abs() < 0.05)
    }

    /// The largest distance [deg] a true joint is from `from` (true angles) over the next
    /// `cycles` cycles.
    pub fn largest_drift(&mut self, from: [f64; 6], cycles: u64) -> f64 {
        let mut drift: f64 = 0.0;
        for _ in 0..cycles {
            self.step(&[]);
            drift = drift.max(max_diff(&from, &self.truth()));
        }
        drift
    }

    pub fn calibrate_all(&mut self) {
        let all = Calibrate {
            which: Which::All,
            elbow_direction: Direction::Positive,
            wrist_direction: Direction::Positive,
            force_mechanical_stop: false,
        };
        self.ok(Request::Calibrate(all), 20_000);
        assert_eq!(self.mode(), Mode::Hold);
    }
}

/// `pvt` with 10 ms between points.
const PVT: Request = Request::Pvt(Pvt { dt_s: 0.01 });

fn torque_control(timeout_s: f64) -> Request {
    Request::TorqueControl(TorqueControl {
        timeout_s: Some(timeout_s),
        gravity_compensation: true,
    })
}

fn move_all(targets_deg: [f64; 6]) -> Request {
    Request::MoveAll(MoveAll {
        targets_deg,
        velocity_factor: 0.5,
    })
}

pub(crate) fn move_axis(axis: u8, target_deg: f64) -> Request {
    Request::MoveAxis(MoveAxis {
        axis: Axis::new(axis).unwrap(),
        target_deg,
        velocity_factor: 0.5,
    })
}

pub(crate) fn max_diff(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn hold_keeps_the_arm_still() {
    let mut r = Robot::new();
    r.ok(Request::Hold, 400);
    assert_eq!(r.mode(), Mode::Hold);
    let before = r.truth();
    r.run(600);
    assert!(
        max_diff(&before, &r.truth()) < 0.01,
        "{before:?} -> {:?}",
        r.truth()
    );
}

#[test]
fn calibration_finds_the_true_angles_and_returns_to_zero() {
    let mut r = Robot::new();
    r.calibrate_all();
    r.run(40);
    let err = max_diff(&r.measured(), &r.truth());
    assert!(
        err < 0.05,
        "reported {:?} vs true {:?}",
        r.measured(),
        r.truth()
    );
    assert!(
        max_diff(&r.truth(), &[0.0; 6]) < 0.1,
        "back at zero: {:?}",
        r.truth()
    );
    assert_ne!(
        r.cycle.state().flags & mcm_shared::sample::STATE_ALL_CALIBRATED,
        0
    );
}

#[test]
fn motion_modes_are_refused_until_calibrated() {
    let mut r = Robot::new();
    r.ok(Request::Hold, 400);
    let axis1 = Reason::NotCalibrated { axis: Axis::ALL[0] };
    for req in [PVT, Request::Release, torque_control(1.0)] {
        assert_eq!(r.refused(req, 10), axis1, "{req:?}");
    }
}

#[test]
fn move_all_arrives_on_time_and_on_target() {
    let mut r = Robot::new();
    r.calibrate_all();
    r.ok(PVT, 10);
    let target = [20.0, -30.0, 45.0, 60.0, -40.0, 90.0];
    let Done::MoveAll(plan) = r.ok(move_all(target), 10) else {
        panic!("move_all answers its plan")
    };
    let duration = plan.duration_s;
    assert!(duration > 0.5, "{plan:?}");
    let start = r.k;
    r.run_until("move done", 4000, |r| {
        max_diff(&r.truth(), &target) < 0.05
            && r.cycle.state().velocity.iter().all(|v| v.abs() < 1e-9)
    });
    let took = (r.k - start) as f64 * 0.005;
    assert!(
        took <= duration * 1.05 + 0.005 + 0.1,
        "took {took} s for {duration} s"
    );
    r.run(100);
    assert!(max_diff(&r.truth(), &target) < 0.05, "{:?}", r.truth());
}

#[test]
fn a_move_while_moving_runs_alongside_and_hold_stops() {
    let mut r = Robot::new();
    r.calibrate_all();
    r.ok(PVT, 10);
    r.ok(move_axis(1, 60.0), 10);
    r.run(100);
    // Accepted: axis 2 starts, axis 1 carries on (more in `moves/tests.rs`).
    r.ok(move_axis(2, 10.0), 10);
    r.ok(Request::Hold, 10);
    assert_eq!(r.mode(), Mode::Hold);
    r.run(200);
    let a = r.truth();
    r.run(100);
    assert!(max_diff(&a, &r.truth()) < 0.01, "stopped and holding");
    assert!(a[0] > 1.0 && a[0] < 60.0, "stopped part way: {a:?}");
}

#[test]
fn release_floats_follows_a_push_and_stays() {
    let mut r = Robot::new();
    r.calibrate_all();
    // Move somewhere gravity matters.
    r.ok(PVT, 10);
    r.ok(move_all([0.0, 45.0, 30.0, 0.0, 30.0, 0.0]), 10);
    r.run_until("moved", 3000, |r| {
        r.cycle.state().velocity.iter().all(|v| v.abs() < 1e-9) && r.k > 10
    });
    r.run(50);
    r.ok(Request::Hold, 10);
    r.ok(Request::Release, 10);
    let a = r.truth();
    r.run(400); // 2 s
    let drift = max_diff(&a, &r.truth()) / 2.0;
    assert!(drift < 0.5, "drift {drift} deg/s: {a:?} -> {:?}", r.truth());
    // A push on axis 1 moves it; after the push it stays.
    let push = |request_id, torques_nm| {
        let mut s = Request::Sim(SimCommand {
            external_torques_nm: Some(torques_nm),
            ..SimCommand::default()
        })
        .encode();
        (s.client_id, s.request_id) = (1, request_id);
        s
    };
    r.step(&[push(999, [5.0, 0.0, 0.0, 0.0, 0.0, 0.0])]);
    r.run(50);
    r.step(&[push(1000, [0.0; 6])]);
    let pushed = r.truth();
    assert!(
        pushed[0] - a[0] > 1.0,
        "the push moved axis 1: {a:?} -> {pushed:?}"
    );
    r.run(200);
    let settled = r.truth();
    r.run(200);
    assert!(
        max_diff(&settled, &r.truth()) < 0.5,
        "stays where left: {settled:?} -> {:?}",
        r.truth()
    );
}

#[test]
fn torque_control_falls_back_to_hold_on_timeout() {
    let mut r = Robot::new();
    r.calibrate_all();
    r.ok(torque_control(0.1), 10);
    assert_eq!(r.mode(), Mode::TorqueControl);
    for _ in 0..10 {
        r.ok(
            Request::SetTorques(SetTorques {
                torques_nm: [0.0; 6],
            }),
            5,
        );
        r.run(5);
    }
    assert_eq!(r.mode(), Mode::TorqueControl);
    r.run(30);
    assert_eq!(r.mode(), Mode::Hold, "no set_torques for 150 ms");
}

#[test]
fn pvt_stream_of_a_sine_tracks_within_a_tenth_of_a_degree() {
    let mut r = Robot::new();
    r.calibrate_all();
    r.ok(PVT, 10);
    // 10 deg amplitude, 0.5 Hz on every axis, from rest: p = A (1 - cos(wt)).
    let amp = 10.0;
    let w = core::f64::consts::PI;
    let point = |k: usize| {
        let t = k as f64 * 0.01;
        (amp * (1.0 - (w * t).cos()), amp * w * (w * t).sin())
    };
    let mut k = 1;
    let mut worst: f64 = 0.0;
    let mut cycles = 0;
    while k <= 400 {
        // Four points per sample, as the gateway sends them.
        let points: [PvtPoint; 4] = core::array::from_fn(|j| {
            let (p, v) = point(k + j);
            PvtPoint {
                position_deg: [p; 6],
                velocity_deg_s: [v; 6],
            }
        });
        let chunk = PvtChunk::new(&points, k % 20 == 17).unwrap();
        let mut s = Request::PvtPoints(chunk).encode();
        (s.client_id, s.request_id) = (5, 5000 + k as u64);
        k += 4;
        r.step(&[s]);
        cycles += 1;
        if cycles > 10 {
            let st = r.cycle.state();
            worst = worst.max(max_diff(&st.commanded_position, &st.sim_true_position));
        }
        // Keep the queue fed without running ahead of it too far.
        while r.cycle.state().pvt_queued > 40 {
            r.step(&[]);
            let st = r.cycle.state();
            worst = worst.max(max_diff(&st.commanded_position, &st.sim_true_position));
        }
    }
    assert!(worst < 0.1, "tracking error {worst} deg");
}

#[test]
fn calibration_survives_a_restart_of_the_mcm_but_not_a_power_cycle() {
    use mcm_shared::sample::{AXIS_CALIBRATED, STATE_ALL_CALIBRATED};
    use mcm_sim::SimControl;
    let cfg = RobotConfig::prob2_default();
    let mut r = Robot::new();
    r.calibrate_all();
    r.run(40);
    let stored = r.cycle.bus_mut().drive(0).unwrap().retained();
    assert_eq!(
        stored.calibration_valid, 1,
        "the drives hold the calibration"
    );
    // Restart: the drives keep their power, the controller and master start from scratch.
    let path = std::env::temp_dir().join(format!(
        "mcm-controller-restart-{}.state",
        std::process::id()
    ));
    r.cycle.bus_mut().save(&path).unwrap();
    let bus = SimBus::resume(&cfg, &path).unwrap().unwrap();
    std::fs::remove_file(&path).unwrap();
    let mut r = Robot {
        cycle: SimCycle::new(&cfg, bus).unwrap(),
        k: 0,
        period: cfg.cycle_period_ns(),
        next_request: 1,
        replies: Vec::new(),
    };
    r.run_until("drives online", 400, |r| {
        r.cycle.controller().feedback().iter().all(|f| f.online)
    });
    r.run(1);
    let flags = r.cycle.state().flags;
    assert_ne!(
        flags & STATE_ALL_CALIBRATED,
        0,
        "calibrated after the restart"
    );
    r.ok(Request::Hold, 400);
    r.run(40);
    let err = max_diff(&r.measured(), &r.truth());
    assert!(
        err < 0.05,
        "reported {:?} vs true {:?}",
        r.measured(),
        r.truth()
    );
    // A power cycle of the drives loses the calibration.
    r.cycle
        .bus_mut()
        .apply(&SimCommand {
            power_cycle: true,
            ..SimCommand::default()
        })
        .unwrap();
    r.run(2);
    r.run_until("drives online again", 400, |r| {
        r.cycle.controller().feedback().iter().all(|f| f.online)
    });
    r.run(2);
    let s = r.cycle.state();
    assert_eq!(s.flags & STATE_ALL_CALIBRATED, 0);
    assert!(
        s.axis_flags.iter().all(|f| f & AXIS_CALIBRATED == 0),
        "{:?}",
        s.axis_flags
    );
}

use mcm_shared::ranges::{Arg, ArgRefusal};

#[test]
fn an_undecodable_sample_is_refused_naming_the_value_and_t_ns_is_the_virtual_time() {
    let mut r = Robot::new();
    // Axis 7 cannot be built as a typed request: a co-located sender's raw sample.
    let mut bad = move_axis(1, 10.0).encode();
    bad.args[0] = 7.0;
    (bad.client_id, bad.request_id) = (9, 77);
    r.step(&[bad]);
    let s = r.cycle.state();
    assert_eq!(
        s.t_ns,
        (r.k - 1) * r.period,
        "the cycle's virtual start time"
    );
    assert_axis_7_refused(&r, 77, Arg::AxisIndex);
    assert_eq!(r.mode(), Mode::Off, "nothing changed");
}

/// The last reply answers request `id` of client 9, refusing axis 7 as out of the range of
/// the argument `arg`.
fn assert_axis_7_refused(r: &Robot, id: u64, arg: Arg) {
    let reply = Response::decode(r.cycle.replies().last().unwrap()).unwrap();
    assert_eq!((reply.client_id, reply.request_id), (9, id));
    assert_eq!(
        reply.outcome,
        Outcome::Refused(Reason::InvalidArgument {
            refusal: ArgRefusal {
                arg,
                axis: None,
                value: 7.0,
                min: 1.0,
                max: 6.0
            }
        })
    );
}

#[test]
fn an_undecodable_sim_sample_is_refused_by_the_controller_like_any_other() {
    use mcm_shared::command::{Axis, SimCommand};
    let mut r = Robot::new();
    // A block of axis 7 cannot be built as a typed request: a raw sample of a co-located sender.
    let mut bad = Request::Sim(SimCommand {
        block_axis: Axis::new(3),
        ..SimCommand::default()
    })
    .encode();
    bad.args[3] = 7.0;
    (bad.client_id, bad.request_id) = (9, 78);
    r.step(&[bad]);
    assert_axis_7_refused(&r, 78, Arg::BlockAxis);
    assert_eq!(
        r.cycle.replies().len(),
        1,
        "answered once, by the controller alone"
    );
    assert_eq!(r.cycle.state().reply_head, 1);
}

/// ERROR powers off a drive the master lost when its axis has a brake (`lost_power_off`), and
/// only that one: the others hold. The master sends it NMT stop while it stays lost, which
/// reaches it once its cable is back, and it aborts its connection (0x6007 = 2); it is then
/// reset and configured again, and `hold` works. With no brakes the lost drive is asked to
/// hold, as the others.
#[test]
fn error_powers_off_a_lost_drive_only_where_its_axis_has_a_brake() {
    use crate::canopen::DriveRequest;
    use mcm_sim::SimControl;
    for brake in [true, false] {
        let mut cfg = RobotConfig::prob2_default();
        for a in &mut cfg.axes {
            a.brake = brake;
        }
        let mut r = Robot::with_config(&cfg);
        r.ok(Request::Hold, 400);
        let sim = |disconnect: bool| SimCommand {
            disconnect_axis: disconnect.then_some(Axis::ALL[2]),
            reconnect_axis: (!disconnect).then_some(Axis::ALL[2]),
            ..SimCommand::default()
        };
        r.cycle.bus_mut().apply(&sim(true)).unwrap();
        r.run_until("the trip", 100, |r| r.mode() == Mode::Error);
        r.run(40);
        let off = r
            .cycle
            .controller()
            .requests()
            .map(|q| q == DriveRequest::Disable);
        assert_eq!(
            off,
            [false, false, brake, false, false, false],
            "brakes {brake}"
        );
        r.cycle.bus_mut().apply(&sim(false)).unwrap();
        r.run(100);
        if brake {
            let aborts = r
                .cycle
                .bus_mut()
                .drive(2)
                .unwrap()
                .counters()
                .connection_aborts;
            assert!(
                aborts > 0,
                "the NMT stop reached the drive once it was back"
            );
        }
        r.run_until("axis 3 online again", 1000, |r| {
            r.cycle.controller().feedback()[2].online
        });
        r.ok(Request::Hold, 1000);
    }
}
