//! The controlled stop and disable of a shutdown, against the simulated robot in virtual time.

use super::{ShutdownPhase, ShutdownResult};
use crate::controller::tests::Robot;
use mcm_shared::command::{Axis, MoveAxis, Pvt, Request};
use mcm_shared::mode::Mode;
use mcm_shared::reply::Reason;
use mcm_shared::sample::{AXIS_ENABLED, STATE_SHUTTING_DOWN};

const PERIOD_S: f64 = 0.005;

/// Axis 1 moving at 45 deg/s (half its 90 deg/s) towards a far target.
fn moving_at_45() -> Robot {
    let mut r = Robot::new();
    r.calibrate_all();
    r.ok(Request::Pvt(Pvt { dt_s: 0.01 }), 10);
    let far = MoveAxis {
        axis: Axis::new(1).unwrap(),
        target_deg: 160.0,
        velocity_factor: 0.5,
    };
    r.ok(Request::MoveAxis(far), 10);
    r.run_until("cruising at 45 deg/s", 1000, |r| {
        (r.cycle.state().sim_true_velocity[0] - 45.0).abs() < 0.5
    });
    r
}

#[test]
fn shutdown_while_moving_stops_within_the_braking_bound_then_disables() {
    let mut r = moving_at_45();
    assert_eq!(r.cycle.state().flags & STATE_SHUTTING_DOWN, 0);
    r.cycle.controller_mut().begin_shutdown();
    let start = r.k;
    r.step(&[]);
    assert_ne!(r.cycle.state().flags & STATE_SHUTTING_DOWN, 0);
    assert_eq!(r.mode(), Mode::Hold, "braking with the stop `hold` uses");

    // Braking at the axis's 180 deg/s^2 from 45 deg/s takes 0.25 s; allow the drives' two
    // cycles of lag and the physics settling.
    let braking_s = 45.0 / 180.0;
    let bound = ((braking_s + 0.1) / PERIOD_S) as u64;
    r.run_until("standstill", bound, |r| r.fastest_true_speed() < 0.05);
    let stopped_after = (r.k - start) as f64 * PERIOD_S;
    assert!(
        stopped_after >= braking_s - 0.02,
        "braked too hard: {stopped_after} s"
    );

    // Commands are refused, `status` still answers.
    let hold = r.refused(Request::Hold, 5);
    assert_eq!(hold, Reason::ShuttingDown);
    let mv = MoveAxis {
        axis: Axis::new(2).unwrap(),
        target_deg: 10.0,
        velocity_factor: 0.5,
    };
    assert_eq!(r.refused(Request::MoveAxis(mv), 5), Reason::ShuttingDown);
    r.ok(Request::Status, 5);

    // Held, then every drive disabled, within the controller's bound.
    let bound_cycles = r.cycle.controller().shutdown_bound_ns() / r.period;
    r.run_until("shutdown done", bound_cycles, |r| {
        r.cycle
            .controller()
            .shutdown_status()
            .and_then(|s| s.result())
            .is_some()
    });
    let status = r.cycle.controller().shutdown_status().unwrap();
    assert_eq!(status.result(), Some(ShutdownResult::Disabled));
    assert!(status.elapsed_ns() >= super::SHUTDOWN_HOLD_NS);
    assert_eq!(r.mode(), Mode::Off);
    let s = r.cycle.state();
    assert!(
        s.axis_flags.iter().all(|f| f & AXIS_ENABLED == 0),
        "{:?}",
        s.axis_flags
    );
    assert_ne!(s.flags & STATE_SHUTTING_DOWN, 0, "stays flagged to the end");
    assert!(r.fastest_true_speed() < 0.05);
}

#[test]
fn shutdown_from_off_disables_at_once_and_a_second_request_changes_nothing() {
    let mut r = Robot::new();
    r.cycle.controller_mut().begin_shutdown();
    r.cycle.controller_mut().begin_shutdown();
    r.run_until("shutdown done", 20, |r| {
        r.cycle
            .controller()
            .shutdown_status()
            .is_some_and(|s| s.phase == ShutdownPhase::Done(ShutdownResult::Disabled))
    });
    assert_eq!(r.mode(), Mode::Off);
}

#[test]
fn a_calibration_under_way_is_told_why_it_ended() {
    use mcm_shared::command::{Calibrate, Direction, Which};
    use mcm_shared::reply::Outcome;
    let mut r = Robot::new();
    let all = Calibrate {
        which: Which::All,
        elbow_direction: Direction::Positive,
        wrist_direction: Direction::Positive,
        force_mechanical_stop: false,
    };
    let mut s = Request::Calibrate(all).encode();
    s.client_id = 7;
    s.request_id = 99;
    r.step(&[s]);
    r.run_until("calibrating", 400, |r| r.mode() == Mode::Calibration);
    r.cycle.controller_mut().begin_shutdown();
    r.step(&[]);
    let reply = r
        .replies
        .iter()
        .find(|x| x.request_id == 99)
        .map(|x| mcm_shared::reply::Response::decode(x).unwrap())
        .expect("the calibration's caller is answered");
    assert_eq!(reply.outcome, Outcome::Failed(Reason::ShuttingDown));
}
