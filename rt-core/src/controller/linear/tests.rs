//! `move_linear` against the simulated robot in virtual time: the reply once planned, the
//! reference on the line, the refusals, and the rules during motion.

use crate::controller::tests::Robot;
use mcm_kinematics::Kinematics;
use mcm_shared::command::{MoveAll, MoveLinear, Pvt, Request};
use mcm_shared::config::RobotConfig;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::mode::Mode;
use mcm_shared::reply::{Done, Outcome, Reason};
use mcm_shared::units::deg_to_rad6;
use nalgebra::Vector3;

/// A pose well inside the workspace, away from every singularity [deg].
const START: [f64; 6] = [20.0, 30.0, 60.0, -40.0, 50.0, 10.0];

fn kin() -> Kinematics {
    Kinematics::from_config(&RobotConfig::prob2_default()).unwrap()
}

/// The TCP's position at joint angles `q_deg` (the configuration's tool: the flange).
fn tcp(q_deg: &[f64; 6]) -> Vector3<f64> {
    kin().tcp_pose(&deg_to_rad6(q_deg)).translation.vector
}

fn line_to(p: Vector3<f64>, velocity: f64) -> Request {
    Request::MoveLinear(MoveLinear {
        position: [p.x, p.y, p.z],
        orientation: None,
        velocity: Some(velocity),
        acceleration: None,
    })
}

/// Calibrated, in PVT, at rest at [`START`].
fn at_start() -> Robot {
    let mut r = Robot::calibrated();
    r.ok(Request::Pvt(Pvt { dt_s: 0.01 }), 10);
    r.ok(
        Request::MoveAll(MoveAll {
            targets_deg: START,
            velocity_factor: 1.0,
        }),
        10,
    );
    r.run_until("at START", 2000, |r| {
        !r.cycle.controller().state.planned_motion()
    });
    r
}

/// The commanded TCP position of the last cycle.
fn commanded_tcp(r: &Robot) -> Vector3<f64> {
    tcp(&r.cycle.state().position)
}

/// Distance of `p` from the segment `a`-`b`.
fn off_line(p: Vector3<f64>, a: Vector3<f64>, b: Vector3<f64>) -> f64 {
    let d = b - a;
    let s = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (p - (a + s * d)).norm()
}

#[test]
fn a_line_is_answered_once_planned_and_the_reference_follows_it() {
    let mut r = at_start();
    let a = commanded_tcp(&r);
    let b = a + Vector3::new(0.0, 0.1, -0.05);
    let Done::MoveLinear(plan) = r.ok(line_to(b, 0.2), 5) else {
        panic!("not a move_linear answer");
    };
    // 11 cm at 0.2 m/s: at least 0.56 s.
    assert!(plan.duration_s > 0.55 && plan.duration_s < 3.0, "{plan:?}");
    let end = tcp(&plan.joint_target_deg);
    assert!(
        (end - b).norm() < 1e-6,
        "the joint target puts the TCP {end} m, not at {b}"
    );
    let mut fastest: f64 = 0.0;
    let mut prev = commanded_tcp(&r);
    let cycles = (plan.duration_s / 0.005).ceil() as u64 + 2;
    for _ in 0..cycles {
        r.step(&[]);
        let p = commanded_tcp(&r);
        assert!(off_line(p, a, b) < 1e-6, "{p} is off the line");
        fastest = fastest.max((p - prev).norm() / 0.005);
        prev = p;
    }
    assert!(
        fastest <= 0.2 * 1.001 && fastest > 0.15,
        "TCP speed {fastest} m/s"
    );
    assert!((commanded_tcp(&r) - b).norm() < 1e-9);
    assert!(!r.cycle.controller().state.planned_motion());
    assert_eq!(r.cycle.state().velocity, [0.0; 6]);
    assert_eq!(r.mode(), Mode::Pvt);
}

#[test]
fn an_unreachable_line_is_refused_naming_where_and_nothing_moves() {
    let mut r = at_start();
    let before = r.cycle.state().position;
    // Straight up by 1.5 m: out of the arm's reach part of the way.
    let far = commanded_tcp(&r) + Vector3::new(0.0, 0.0, 1.5);
    let why = r.refused(line_to(far, 0.25), 5);
    assert_eq!(why.error_code(), ErrorCode::Unreachable, "{why}");
    let Reason::LineUnreachable { fault, .. } = why else {
        panic!("{why:?}");
    };
    assert!(fault.fraction() > 0.0 && fault.fraction() < 1.0, "{why}");
    assert!(why.to_string().contains("% of the path"), "{why}");
    // Along x by 2 m axis 5 leaves its reachable range first: out_of_range, naming it.
    let far = commanded_tcp(&r) + Vector3::new(2.0, 0.0, 0.0);
    let why = r.refused(line_to(far, 0.25), 5);
    assert_eq!(why.error_code(), ErrorCode::OutOfRange, "{why}");
    assert!(matches!(why, Reason::LineOutOfRange { .. }), "{why:?}");
    r.run(20);
    assert_eq!(r.cycle.state().position, before);
    assert_eq!(r.mode(), Mode::Pvt);
}

#[test]
fn move_linear_outside_pvt_is_refused_wrong_mode() {
    let mut r = Robot::calibrated();
    let p = tcp(&r.cycle.state().position);
    assert!(matches!(
        r.refused(line_to(p, 0.1), 5),
        Reason::WrongMode { .. }
    ));
}

#[test]
fn a_line_during_a_move_stops_the_move_first_then_runs_from_where_it_stopped() {
    let mut r = at_start();
    let mut goal = START;
    goal[0] += 40.0;
    r.ok(
        Request::MoveAll(MoveAll {
            targets_deg: goal,
            velocity_factor: 1.0,
        }),
        10,
    );
    r.run(60);
    assert!(r.cycle.state().velocity[0].abs() > 10.0, "moving");
    let b = commanded_tcp(&r) + Vector3::new(0.0, 0.0, 0.05);
    let mut s = line_to(b, 0.1).encode();
    (s.client_id, s.request_id) = (42, 900);
    let mut prev = r.cycle.state().velocity;
    r.step(&[s]);
    // The move comes to rest within each axis's acceleration limit (no step in velocity),
    // and only then is the line answered.
    let plan = loop {
        let v = r.cycle.state().velocity;
        for i in 0..6 {
            let step = (v[i] - prev[i]).abs();
            assert!(
                step <= 300.0 * 0.005 + 1e-6,
                "axis {}: {step} deg/s in a cycle",
                i + 1
            );
        }
        prev = v;
        let reply = r
            .cycle
            .replies()
            .iter()
            .find(|x| x.request_id == 900)
            .copied();
        if let Some(reply) = reply {
            let answer = mcm_shared::reply::Response::decode(&reply).unwrap().outcome;
            let Outcome::Done(Done::MoveLinear(plan)) = answer else {
                panic!("{answer:?}");
            };
            // The line's first cycle: it started from rest.
            assert!(v.iter().all(|x| x.abs() < 0.1), "{v:?}");
            break plan;
        }
        assert!(r.k < 5000, "no answer");
        r.step(&[]);
    };
    // The line starts at rest where the move stopped, past `here`, and ends at `b`.
    let cycles = (plan.duration_s / 0.005).ceil() as u64 + 2;
    r.run(cycles);
    assert!((commanded_tcp(&r) - b).norm() < 1e-9);
    assert!(!r.cycle.controller().state.planned_motion());
}

#[test]
fn hold_during_a_line_stops_it_and_a_move_during_a_line_replans_from_it() {
    let mut r = at_start();
    let a = commanded_tcp(&r);
    r.ok(line_to(a + Vector3::new(0.0, 0.15, 0.0), 0.25), 5);
    r.run(40);
    // A move_all re-plans each axis from the line's present reference: no velocity step.
    let v0 = r.cycle.state().velocity;
    assert!(v0.iter().any(|v| v.abs() > 1.0));
    let Done::MoveAll(_) = r.ok(
        Request::MoveAll(MoveAll {
            targets_deg: START,
            velocity_factor: 0.5,
        }),
        2,
    ) else {
        panic!("not a move_all answer");
    };
    let v1 = r.cycle.state().velocity;
    for i in 0..6 {
        assert!(
            (v1[i] - v0[i]).abs() <= 300.0 * 0.005 * 2.0 + 1e-6,
            "axis {}: {} -> {} deg/s",
            i + 1,
            v0[i],
            v1[i]
        );
    }
    r.run_until("back at START", 2000, |r| {
        !r.cycle.controller().state.planned_motion()
    });
    // hold during a line: the controlled stop to HOLD.
    let a = commanded_tcp(&r);
    r.ok(line_to(a + Vector3::new(0.0, 0.15, 0.0), 0.25), 5);
    r.run(40);
    r.ok(Request::Hold, 2);
    assert_eq!(r.mode(), Mode::Hold);
    r.run_until("at rest", 400, |r| r.at_rest());
}

#[test]
fn a_second_line_while_one_waits_supersedes_it() {
    let mut r = at_start();
    let a = commanded_tcp(&r);
    let mut s1 = line_to(a + Vector3::new(0.0, 0.05, 0.0), 0.1).encode();
    let mut s2 = line_to(a + Vector3::new(0.0, 0.0, 0.05), 0.1).encode();
    (s1.client_id, s1.request_id) = (42, 1001);
    (s2.client_id, s2.request_id) = (42, 1002);
    r.step(&[s1, s2]);
    r.run(3);
    let outcome = |id| {
        r.replies
            .iter()
            .find(|x| x.request_id == id)
            .map(|x| mcm_shared::reply::Response::decode(x).unwrap().outcome)
    };
    assert_eq!(outcome(1001), Some(Outcome::Failed(Reason::Aborted)));
    assert!(matches!(
        outcome(1002),
        Some(Outcome::Done(Done::MoveLinear(_)))
    ));
}
