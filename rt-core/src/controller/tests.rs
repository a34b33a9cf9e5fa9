//! Scenario tests of the controller against the simulated robot, in virtual time: the whole
//! robot (controller, CANopen master, simulated drives, physics) stepped cycle by cycle, with
//! the simulator's edge as the runner wires it in ([`SimCycle`]).

use crate::sim_edge::SimCycle;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode, RejectCode, ReplyStatus};
use mcm_shared::sample::{CommandSample, Reply};
use mcm_sim::SimBus;

pub(crate) struct Robot {
    pub cycle: SimCycle,
    pub k: u64,
    pub period: u64,
    next_request: u64,
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
        };
        r.run_until("drives online", 400, |r| {
            r.cycle.controller().feedback().iter().all(|f| f.online)
        });
        r
    }

    pub fn step(&mut self, commands: &[CommandSample]) {
        self.cycle.run(self.k * self.period, commands);
        self.k += 1;
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

    /// Send one command and run until its reply arrives (at most `max_cycles`).
    pub fn command(
        &mut self,
        kind: CommandKind,
        args: &[f64],
        flags: u32,
        max_cycles: u64,
    ) -> Reply {
        let mut s = CommandSample {
            client_id: 42,
            request_id: self.next_request,
            kind: kind.to_wire(),
            flags,
            ..CommandSample::default()
        };
        s.args[..args.len()].copy_from_slice(args);
        self.next_request += 1;
        let id = s.request_id;
        let head = self.cycle.controller().state().reply_head;
        self.step(&[s]);
        for _ in 0..max_cycles {
            let st = self.cycle.controller().state();
            for n in head + 1..=st.reply_head {
                if let Some(r) = st.reply(n)
                    && r.request_id == id
                {
                    return *r;
                }
            }
            self.step(&[]);
        }
        panic!("no reply to {kind:?} within {max_cycles} cycles");
    }

    pub fn ok(&mut self, kind: CommandKind, args: &[f64], max_cycles: u64) -> Reply {
        let r = self.command(kind, args, 0, max_cycles);
        assert_eq!(
            r.status,
            ReplyStatus::Ok.to_wire(),
            "{kind:?} failed: {r:?}"
        );
        r
    }

    /// Measured joint positions [deg], as reported.
    pub fn measured(&self) -> [f64; 6] {
        self.cycle.controller().state().measured_position
    }

    /// The simulation's true joint angles [deg].
    pub fn truth(&self) -> [f64; 6] {
        self.cycle.controller().state().sim_true_position
    }

    pub fn calibrate_all(&mut self) {
        self.ok(CommandKind::Calibrate, &[0.0, 1.0, 1.0], 20_000);
        assert_eq!(self.mode(), Mode::Hold);
    }
}

fn max_diff(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn hold_keeps_the_arm_still() {
    let mut r = Robot::new();
    r.ok(CommandKind::Hold, &[], 400);
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
        r.cycle.controller().state().flags & mcm_shared::sample::STATE_ALL_CALIBRATED,
        0
    );
}

#[test]
fn motion_modes_are_refused_until_calibrated() {
    let mut r = Robot::new();
    r.ok(CommandKind::Hold, &[], 400);
    for kind in [CommandKind::Pvt, CommandKind::Release] {
        let rep = r.command(kind, &[0.01], 0, 10);
        assert_eq!(
            rep.code,
            RejectCode::NotCalibrated.to_wire(),
            "{kind:?}: {rep:?}"
        );
        assert_eq!(rep.axis, 1);
    }
    let rep = r.command(CommandKind::TorqueControl, &[1.0], 0, 10);
    assert_eq!(rep.code, RejectCode::NotCalibrated.to_wire());
}

#[test]
fn move_all_arrives_on_time_and_on_target() {
    let mut r = Robot::new();
    r.calibrate_all();
    r.ok(CommandKind::Pvt, &[0.01], 10);
    let target = [20.0, -30.0, 45.0, 60.0, -40.0, 90.0];
    let mut args = target.to_vec();
    args.push(0.5);
    let rep = r.ok(CommandKind::MoveAll, &args, 10);
    let duration = rep.values[7];
    assert!(duration > 0.5, "{rep:?}");
    let start = r.k;
    r.run_until("move done", 4000, |r| {
        max_diff(&r.truth(), &target) < 0.05
            && r.cycle
                .controller()
                .state()
                .velocity
                .iter()
                .all(|v| v.abs() < 1e-9)
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
fn move_while_moving_is_busy_and_hold_stops() {
    let mut r = Robot::new();
    r.calibrate_all();
    r.ok(CommandKind::Pvt, &[0.01], 10);
    r.ok(CommandKind::MoveAxis, &[1.0, 60.0, 0.5], 10);
    r.run(100);
    let rep = r.command(CommandKind::MoveAxis, &[2.0, 10.0, 0.5], 0, 10);
    assert_eq!(rep.code, RejectCode::Busy.to_wire(), "{rep:?}");
    r.ok(CommandKind::Hold, &[], 10);
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
    r.ok(CommandKind::Pvt, &[0.01], 10);
    r.ok(
        CommandKind::MoveAll,
        &[0.0, 45.0, 30.0, 0.0, 30.0, 0.0, 0.5],
        10,
    );
    r.run_until("moved", 3000, |r| {
        r.cycle
            .controller()
            .state()
            .velocity
            .iter()
            .all(|v| v.abs() < 1e-9)
            && r.k > 10
    });
    r.run(50);
    r.ok(CommandKind::Hold, &[], 10);
    r.ok(CommandKind::Release, &[], 10);
    let a = r.truth();
    r.run(400); // 2 s
    let drift = max_diff(&a, &r.truth()) / 2.0;
    assert!(drift < 0.5, "drift {drift} deg/s: {a:?} -> {:?}", r.truth());
    // A push on axis 1 moves it; after the push it stays.
    let mut sim = CommandSample {
        client_id: 1,
        request_id: 999,
        kind: CommandKind::Sim.to_wire(),
        flags: 1 << 5,
        ..CommandSample::default()
    };
    sim.args[5] = 5.0;
    r.step(&[sim]);
    r.run(50);
    sim.args[5] = 0.0;
    sim.request_id = 1000;
    r.step(&[sim]);
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
    r.ok(CommandKind::TorqueControl, &[0.1], 10);
    assert_eq!(r.mode(), Mode::TorqueControl);
    for _ in 0..10 {
        r.ok(CommandKind::SetTorques, &[0.0; 6], 5);
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
    r.ok(CommandKind::Pvt, &[0.01], 10);
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
        let mut s = CommandSample {
            client_id: 5,
            request_id: 5000 + k as u64,
            kind: CommandKind::PvtPoints.to_wire(),
            flags: 4 | if k % 20 == 17 {
                mcm_shared::sample::PVT_FLAG_LAST
            } else {
                0
            },
            ..CommandSample::default()
        };
        for j in 0..4 {
            let (p, v) = point(k + j);
            for i in 0..6 {
                s.args[j * 12 + i] = p;
                s.args[j * 12 + 6 + i] = v;
            }
        }
        k += 4;
        r.step(&[s]);
        cycles += 1;
        if cycles > 10 {
            let st = r.cycle.controller().state();
            worst = worst.max(max_diff(&st.commanded_position, &st.sim_true_position));
        }
        // Keep the queue fed without running ahead of it too far.
        while r.cycle.controller().state().pvt_queued > 40 {
            r.step(&[]);
            let st = r.cycle.controller().state();
            worst = worst.max(max_diff(&st.commanded_position, &st.sim_true_position));
        }
    }
    assert!(worst < 0.1, "tracking error {worst} deg");
}

#[test]
fn calibration_survives_a_restart_of_the_mcm_but_not_a_power_cycle() {
    use mcm_shared::sample::{AXIS_CALIBRATED, STATE_ALL_CALIBRATED};
    use mcm_sim::{SimCommand, SimControl};
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
    };
    r.run_until("drives online", 400, |r| {
        r.cycle.controller().feedback().iter().all(|f| f.online)
    });
    r.run(1);
    let flags = r.cycle.controller().state().flags;
    assert_ne!(
        flags & STATE_ALL_CALIBRATED,
        0,
        "calibrated after the restart"
    );
    r.ok(CommandKind::Hold, &[], 400);
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
    let s = r.cycle.controller().state();
    assert_eq!(s.flags & STATE_ALL_CALIBRATED, 0);
    assert!(
        s.axis_flags.iter().all(|f| f & AXIS_CALIBRATED == 0),
        "{:?}",
        s.axis_flags
    );
}
