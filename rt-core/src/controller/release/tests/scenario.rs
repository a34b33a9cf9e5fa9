//! Scenario tests of RELEASE's soft speed limit in virtual time (the whole simulated robot,
//! see `controller/tests.rs`): pushes of increasing torque against the simulation's truth.

use crate::controller::tests::Robot;
use crate::controller::trips::RELAX_CYCLES;
use mcm_shared::command::{Axis, MoveAxis, Pvt, Request, SimCommand};
use mcm_shared::mode::Mode;
use mcm_shared::reply::Reason;

fn sim(r: &mut Robot, request_id: u64, c: SimCommand) {
    let mut s = Request::Sim(c).encode();
    (s.client_id, s.request_id) = (1, request_id);
    r.step(&[s]);
}

fn push(r: &mut Robot, request_id: u64, torques_nm: [f64; 6]) {
    let c = SimCommand {
        external_torques_nm: Some(torques_nm),
        ..SimCommand::default()
    };
    sim(r, request_id, c);
}

/// Pushes on axis 1 in RELEASE for 0.7 s each (alternating direction): up to 10 Nm the true
/// speed stays below the 90 deg/s limit and nothing trips; 30 Nm accelerates the light arm
/// beyond what the damping can catch with its measurement delay, and the hard
/// `velocity_limit` check stops it.
#[test]
fn a_push_in_release_is_slowed_below_the_velocity_limit() {
    let mut r = Robot::new();
    r.calibrate_all();
    r.ok(Request::Release, 10);
    let limit = 90.0;
    let mut id = 100;
    let mut sign = 1.0;
    for nm in [4.0, 6.0, 8.0, 10.0] {
        let mut t = [0.0; 6];
        t[0] = sign * nm;
        id += 1;
        push(&mut r, id, t);
        let mut peak: f64 = 0.0;
        for _ in 0..140 {
            r.step(&[]);
            peak = peak.max(r.cycle.state().sim_true_velocity[0].abs());
        }
        id += 1;
        push(&mut r, id, [0.0; 6]);
        for _ in 0..400 {
            r.step(&[]);
            peak = peak.max(r.cycle.state().sim_true_velocity[0].abs());
        }
        let rest = r.cycle.state().sim_true_velocity[0].abs();
        eprintln!(
            "RELEASE, axis 1 pushed with {nm} Nm for 0.7 s: true speed peaked at {peak:.1} deg/s (limit {limit}), {rest:.2} deg/s 2 s after, at {:.1} deg",
            r.truth()[0]
        );
        assert_eq!(r.mode(), Mode::Release, "{nm} Nm: no trip");
        assert!(peak < limit, "{nm} Nm: {peak} deg/s");
        assert!(
            peak > 0.4 * limit,
            "{nm} Nm moves the arm fast: {peak} deg/s"
        );
        assert!(
            rest < 1.0,
            "{nm} Nm: at rest after letting go, {rest} deg/s"
        );
        sign = -sign;
    }
    // Beyond what the damping can catch: the hard check is the last resort.
    let errors_before = r.cycle.controller().view().last_error.map_or(0, |e| e.seq);
    id += 1;
    push(&mut r, id, [sign * 30.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    r.run_until("the velocity check trips", 140, |r| r.mode() == Mode::Error);
    let e = r.cycle.controller().view().last_error.expect("an error");
    assert_eq!(e.seq, errors_before + 1);
    assert!(
        matches!(e.reason, Reason::VelocityLimit { axis, .. } if axis.index() == 0),
        "{:?}",
        e.reason
    );
}

/// A simulated power cycle reboots every drive at once: the one error of the incident names
/// all six axes, not only the first.
#[test]
fn a_power_cycle_names_every_axis_it_affected() {
    let mut r = Robot::new();
    r.ok(Request::Hold, 400);
    let mut s = Request::Sim(SimCommand {
        power_cycle: true,
        ..SimCommand::default()
    })
    .encode();
    (s.client_id, s.request_id) = (1, 7);
    r.step(&[s]);
    r.run_until("the trip", 20, |r| r.mode() == Mode::Error);
    r.run(10);
    let e = r.cycle.controller().view().last_error.expect("an error");
    assert_eq!(e.seq, 1, "one error for the incident");
    let Reason::DriveDisconnected { axis, also } = e.reason else {
        panic!("{:?}", e.reason)
    };
    assert_eq!((axis.number(), also | 1), (1, 0b11_1111), "{:?}", e.reason);
    assert_eq!(
        e.reason.to_string(),
        "the drives of axes 1, 2, 3, 4, 5 and 6 do not answer on the bus"
    );
}

/// After a following-error trip against an obstacle the drive's loop is restarted where the
/// axis stands: no current into the obstacle in ERROR, and after `hold` and the obstacle's
/// removal the axis stays where it stood.
#[test]
fn no_wound_up_current_after_a_following_error_trip_against_an_obstacle() {
    let mut r = Robot::new();
    r.calibrate_all();
    r.ok(Request::Pvt(Pvt { dt_s: 0.01 }), 10);
    let axis1 = Axis::new(1).unwrap();
    r.ok(
        Request::MoveAxis(MoveAxis {
            axis: axis1,
            target_deg: 60.0,
            velocity_factor: 0.5,
        }),
        10,
    );
    r.run_until("axis 1 moving", 400, |r| {
        r.cycle.state().sim_true_velocity[0] > 10.0
    });
    let block = SimCommand {
        block_axis: Some(axis1),
        ..SimCommand::default()
    };
    sim(&mut r, 1, block);
    r.run_until("the trip", 200, |r| r.mode() == Mode::Error);
    let e = r.cycle.controller().view().last_error.expect("an error");
    assert!(
        matches!(e.reason, Reason::FollowingError { .. }),
        "{:?}",
        e.reason
    );
    // The axis springs back off the obstacle while its loop follows it, then holds there: the
    // loop is not restarted again at the end of the relax, which would drop what its integral
    // carries against the obstacle's spring and let the loop creep back to its position later.
    let settle = u64::from(RELAX_CYCLES) + 10;
    r.run(settle);
    let relaxed = r.truth();
    let crept = r.largest_drift(relaxed, 600 - settle); // until 3 s after the trip
    assert!(
        crept < 0.002,
        "the axis holds where it relaxed to: it crept {crept:.4} deg from {relaxed:?}"
    );
    let current = r.cycle.controller().feedback()[0].current_a;
    let stands = r.truth();
    eprintln!("obstacle: 3 s after the trip the drive of axis 1 draws {current:.2} A");
    // Without the restart it pressed with the full 10 A until `hold`; about 1 A is left (the
    // loop holding the axis against the obstacle's spring where it came to rest).
    assert!(
        current.abs() < 2.0,
        "not pressing into the obstacle: {current} A"
    );
    r.ok(Request::Hold, 400);
    let unblock = SimCommand {
        unblock_axis: Some(axis1),
        ..SimCommand::default()
    };
    sim(&mut r, 2, unblock);
    let mut jump: f64 = 0.0;
    for _ in 0..200 {
        r.step(&[]);
        jump = jump.max((r.truth()[0] - stands[0]).abs());
    }
    eprintln!("obstacle: after hold and unblock axis 1 moved up to {jump:.4} deg");
    assert!(jump < 0.05, "no spring when the obstacle goes: {jump} deg");
}

/// A configuration whose elbow range (5..135 deg) leaves out the zero that calibration
/// returns to: in RELEASE the elbow at rest beyond its limit is allowed, a push further out
/// trips `position_limit` with its figures, and the arm stops.
#[test]
fn a_push_beyond_a_joint_limit_trips_position_limit_and_the_arm_stops() {
    let mut cfg = mcm_shared::config::RobotConfig::prob2_default();
    cfg.axes[2].min_deg = 5.0;
    cfg.sim.initial_position_deg[2] = 10.0;
    cfg.validate().expect("a valid configuration");
    let mut r = Robot::with_config(&cfg);
    r.calibrate_all();
    r.run(100);
    assert!(
        r.truth()[2].abs() < 0.1,
        "the elbow at zero: {:?}",
        r.truth()
    );
    r.ok(Request::Release, 10);
    r.run(100);
    assert_eq!(
        r.mode(),
        Mode::Release,
        "at rest beyond the limit is allowed"
    );
    push(&mut r, 1, [0.0, 0.0, -20.0, 0.0, 0.0, 0.0]);
    r.run_until("the trip", 100, |r| r.mode() == Mode::Error);
    let e = r.cycle.controller().view().last_error.expect("an error");
    let Reason::PositionLimit {
        axis,
        position_deg,
        limit_deg,
    } = e.reason
    else {
        panic!("{:?}", e.reason)
    };
    eprintln!("position limit: {}", e.reason);
    assert_eq!((axis.number(), limit_deg), (3, 5.0));
    assert!(position_deg < 5.0, "{position_deg}");
    push(&mut r, 2, [0.0; 6]);
    r.run(200);
    let v = r.cycle.state().sim_true_velocity[2];
    assert!(v.abs() < 0.01, "the elbow stopped: {v} deg/s");
    assert!(
        r.truth()[2] > -2.0,
        "stopped near where it tripped: {:?}",
        r.truth()
    );
}

/// Entering HOLD under gravity (from RELEASE, and after a move) with the gravity load as the
/// drives' torque feed-forward: the true arm sags less than 0.02 deg.
#[test]
fn entering_hold_under_gravity_sags_less_than_0_02_deg() {
    let mut r = Robot::new();
    r.calibrate_all();
    r.ok(Request::Pvt(Pvt { dt_s: 0.01 }), 10);
    r.ok(
        Request::MoveAll(mcm_shared::command::MoveAll {
            targets_deg: [0.0, 60.0, 30.0, 0.0, 30.0, 0.0],
            velocity_factor: 0.5,
        }),
        10,
    );
    r.run_until("moved", 3000, |r| {
        r.cycle.state().velocity.iter().all(|v| v.abs() < 1e-9) && r.k > 10
    });
    r.run(100); // settled
    let drift = r.largest_drift(r.truth(), 200);
    eprintln!("PVT at rest after the move: the true arm moved up to {drift:.4} deg in 1 s");
    // After the move: hold.
    let before = r.truth();
    r.ok(Request::Hold, 10);
    let sag = r.largest_drift(before, 200);
    eprintln!("HOLD after a move: the true arm moved up to {sag:.4} deg");
    assert!(sag < 0.02, "after a move: {sag} deg");
    // From RELEASE, at rest.
    r.ok(Request::Release, 10);
    r.run(200);
    let before = r.truth();
    r.ok(Request::Hold, 10);
    let sag = r.largest_drift(before, 200);
    eprintln!("HOLD from RELEASE: the true arm moved up to {sag:.4} deg");
    assert!(sag < 0.02, "from RELEASE: {sag} deg");
}
