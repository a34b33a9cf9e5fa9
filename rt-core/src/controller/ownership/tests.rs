//! Scenario tests of control ownership (`ownership.rs`): which client may move the arm, that a
//! stop is open to all, and that what a gone owner drove ends in HOLD (virtual time, the whole
//! simulated robot, as in `controller/tests.rs`).

use crate::controller::tests::{Robot, move_axis};
use mcm_shared::command::{Calibrate, Direction, Pvt, Request, SetTorques, TorqueControl, Which};
use mcm_shared::mode::Mode;
use mcm_shared::reply::{Done, Outcome, Reason};

/// The client every `Robot::ok`/`refused` call speaks as.
const A: u64 = 42;
const B: u64 = 7;

fn torque_forever() -> Request {
    Request::TorqueControl(TorqueControl {
        timeout_s: None,
        gravity_compensation: true,
    })
}

fn set_torques(torques_nm: [f64; 6]) -> Request {
    Request::SetTorques(SetTorques { torques_nm })
}

fn outcome(r: &mut Robot, client: u64, req: Request) -> Outcome {
    r.command_from(client, req, 10).outcome
}

fn owner(r: &Robot) -> u64 {
    r.cycle.state().owner_client_id
}

/// A calibrated robot in HOLD; the calibration made client A the owner (implicit take).
fn calibrated() -> Robot {
    let mut r = Robot::new();
    assert_eq!(owner(&r), 0, "nobody owns the arm at start");
    r.calibrate_all();
    assert_eq!(owner(&r), A, "the first calibrate took control");
    r
}

#[test]
fn another_clients_motion_is_refused_naming_the_owner_and_its_hold_works() {
    let mut r = calibrated();
    r.ok(Request::Pvt(Pvt { dt_s: 0.01 }), 5);
    assert_eq!(
        outcome(&mut r, B, move_axis(1, 20.0)),
        Outcome::Refused(Reason::NotOwner { owner: A })
    );
    assert_eq!(
        outcome(&mut r, B, Request::TakeControl),
        Outcome::Refused(Reason::NotOwner { owner: A })
    );
    assert_eq!(
        outcome(&mut r, B, Request::ReleaseControl),
        Outcome::Refused(Reason::NotOwner { owner: A })
    );
    assert_eq!(r.mode(), Mode::Pvt, "refusals change nothing");
    r.ok(move_axis(1, 20.0), 5);
    assert_eq!(
        outcome(&mut r, B, Request::Hold),
        Outcome::Done(Done::Ack),
        "a stop is open to all"
    );
    assert_eq!(r.mode(), Mode::Hold);
    assert_eq!(owner(&r), A, "a stop does not take control");
    assert_eq!(
        outcome(&mut r, B, Request::Status),
        Outcome::Done(Done::Ack)
    );
}

#[test]
fn take_and_release_hand_control_over() {
    let mut r = calibrated();
    r.ok(Request::TakeControl, 2);
    assert_eq!(owner(&r), A, "taking what one owns is OK");
    r.ok(Request::ReleaseControl, 2);
    assert_eq!(owner(&r), 0);
    r.ok(Request::ReleaseControl, 2);
    assert_eq!(
        outcome(&mut r, B, Request::TakeControl),
        Outcome::Done(Done::Ack)
    );
    assert_eq!(owner(&r), B);
    assert_eq!(
        r.refused(Request::Pvt(Pvt { dt_s: 0.01 }), 5),
        Reason::NotOwner { owner: B }
    );
    // A client gone that owns nothing changes nothing.
    r.ok(Request::ClientGone, 2);
    assert_eq!(owner(&r), B);
    assert_eq!(
        outcome(&mut r, B, Request::Pvt(Pvt { dt_s: 0.01 })),
        Outcome::Done(Done::Ack)
    );
    assert_eq!(r.mode(), Mode::Pvt);
}

#[test]
fn client_id_zero_never_gets_control() {
    let mut r = Robot::new();
    assert_eq!(
        outcome(&mut r, 0, Request::TakeControl),
        Outcome::Refused(Reason::NotOwner { owner: 0 })
    );
    assert_eq!(
        outcome(&mut r, 0, Request::Release),
        Outcome::Refused(Reason::NotOwner { owner: 0 })
    );
    assert_eq!(owner(&r), 0);
}

#[test]
fn another_clients_set_torques_is_refused_in_a_torque_session() {
    let mut r = calibrated();
    r.ok(torque_forever(), 5);
    r.ok(set_torques([0.0, 0.0, 0.0, 0.0, 0.0, 0.5]), 5);
    assert_eq!(
        outcome(&mut r, B, set_torques([0.0, 0.0, 0.0, 0.0, 0.0, 3.0])),
        Outcome::Refused(Reason::NotOwner { owner: A })
    );
    r.run(40);
    assert_eq!(r.mode(), Mode::TorqueControl);
    // Axis 6 turns under the owner's 0.5 Nm, not the other client's 3 Nm.
    let v6 = r.cycle.state().sim_true_velocity[5];
    assert!(v6 > 0.0, "the owner's torque acts: {v6} deg/s");
    assert_eq!(outcome(&mut r, B, Request::Hold), Outcome::Done(Done::Ack));
    assert_eq!(r.mode(), Mode::Hold);
}

#[test]
fn a_torque_session_without_timeout_whose_owner_is_gone_stops_in_hold() {
    let mut r = calibrated();
    r.ok(torque_forever(), 5);
    r.ok(set_torques([0.0, 0.0, 0.0, 0.0, 0.0, 1.0]), 5);
    r.run(10);
    assert_eq!(r.mode(), Mode::TorqueControl);
    let before = r.fastest_true_speed();
    assert!(before > 5.0, "the arm turns: {before} deg/s");
    r.ok(Request::ClientGone, 1);
    assert_eq!(r.mode(), Mode::Hold, "HOLD within the cycle that saw it");
    assert_eq!(owner(&r), 0);
    r.run_until("the arm at rest", 400, |r| r.fastest_true_speed() < 0.5);
    let at_rest = r.truth();
    r.run(100);
    let drift = r
        .truth()
        .iter()
        .zip(at_rest)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(drift < 0.2, "held where it stopped: drift {drift} deg");
    assert_eq!(r.mode(), Mode::Hold);
}

#[test]
fn releasing_control_ends_a_move_a_stream_and_release_mode_in_hold() {
    let mut r = calibrated();
    r.ok(Request::Pvt(Pvt { dt_s: 0.01 }), 5);
    r.ok(move_axis(1, 40.0), 5);
    r.run(80);
    r.ok(Request::ReleaseControl, 1);
    assert_eq!(r.mode(), Mode::Hold);
    r.run_until("the arm at rest", 400, |r| r.fastest_true_speed() < 0.5);
    let q1 = r.truth()[0];
    assert!(q1 > 1.0 && q1 < 39.0, "stopped on the way: {q1} deg");

    r.ok(Request::Release, 5);
    assert_eq!(r.mode(), Mode::Release);
    r.ok(Request::ClientGone, 1);
    assert_eq!(r.mode(), Mode::Hold, "RELEASE of a gone owner ends in HOLD");
}

#[test]
fn a_calibration_whose_owner_is_gone_is_aborted_and_holds() {
    let mut r = Robot::new();
    let cal = Request::Calibrate(Calibrate {
        which: Which::All,
        elbow_direction: Direction::Positive,
        wrist_direction: Direction::Positive,
        force_mechanical_stop: false,
    });
    // From OFF: the enabling that was to start the calibration ends in HOLD instead.
    let mut s = cal.encode();
    (s.client_id, s.request_id) = (A, 9000);
    r.step(&[s]);
    r.ok(Request::ClientGone, 1);
    r.run_until("HOLD", 1000, |r| r.mode() == Mode::Hold);
    r.run(50);
    assert_eq!(r.mode(), Mode::Hold, "no calibration started");
    // Nothing was calibrated: the `calibrate` is answered `aborted`, never OK.
    let answers: Vec<_> = r
        .replies
        .iter()
        .filter(|rep| rep.request_id == 9000)
        .map(|rep| mcm_shared::reply::Response::decode(rep).expect("a well-formed reply"))
        .collect();
    assert_eq!(answers.len(), 1, "{answers:?}");
    assert_eq!(answers[0].outcome, Outcome::Failed(Reason::Aborted));
    // A calibration under way is aborted, its caller told so.
    let mut s = cal.encode();
    (s.client_id, s.request_id) = (A, 9001);
    r.step(&[s]);
    r.run(20);
    assert_eq!(r.mode(), Mode::Calibration);
    r.ok(Request::ClientGone, 1);
    assert_eq!(r.mode(), Mode::Hold);
    let aborted = r.replies.iter().rev().find(|rep| rep.request_id == 9001);
    let aborted = mcm_shared::reply::Response::decode(aborted.expect("the calibration answered"))
        .expect("a well-formed reply");
    assert_eq!(aborted.outcome, Outcome::Failed(Reason::Aborted));
    assert_eq!(owner(&r), 0);
}
