//! One case per invariant: a cycle that breaks it is a violation naming what broke, and the
//! same cycle without the defect passes (so that each case fails without its check).

use super::*;
use crate::stamp::calibrate_all;
use mcm_shared::command::{Calibrate, Direction, Pvt};
use mcm_shared::reply::{Done, Reason};
use mcm_shared::sample::{
    AXIS_CALIBRATED, AXIS_ONLINE, STATE_ALL_CALIBRATED, STATE_CARTESIAN, STATE_ESTOP,
};

/// An axis calibrated, its drive online.
const CALIBRATED: u32 = AXIS_CALIBRATED | AXIS_ONLINE;

const CLIENT: u64 = 100;

fn checker() -> Checker {
    let cfg = RobotConfig::prob2_default();
    Checker::new(&cfg, &SimBus::new(&cfg))
}

/// The arm at zero (inside every limit), in `mode`, every axis calibrated and measured right.
fn state(mode: Mode) -> StateSample {
    StateSample {
        mode: mode.to_wire(),
        axis_flags: [CALIBRATED; NUM_AXES],
        ..StateSample::default()
    }
}

fn sample(r: Request, request_id: u64) -> CommandSample {
    let mut c = r.encode();
    (c.client_id, c.request_id) = (CLIENT, request_id);
    c
}

fn answer(request_id: u64, kind: CommandKind, outcome: Outcome) -> Reply {
    Response {
        client_id: CLIENT,
        request_id,
        kind,
        outcome,
    }
    .encode()
}

fn ok(request_id: u64, kind: CommandKind) -> Reply {
    answer(request_id, kind, Outcome::Done(Done::Ack))
}

/// Cycle `k` with no faults and no allocation; the violation's message, if any.
fn check(c: &mut Checker, k: u64, s: &StateSample, replies: &[Reply]) -> Result<(), String> {
    check_served(c, k, s, replies, &[])
}

/// [`check`] with the commands the cycle served, in order.
fn check_served(
    c: &mut Checker,
    k: u64,
    s: &StateSample,
    replies: &[Reply],
    served: &[CommandSample],
) -> Result<(), String> {
    c.cycle(k, s, replies, served, Work::default(), &[])
        .map_err(|v| {
            assert_eq!(v.cycle, k);
            assert!(!v.quiet_phase);
            v.message
        })
}

fn broken(r: Result<(), String>, what: &str) {
    match r {
        Err(m) => assert!(m.contains(what), "expected {what:?} in {m:?}"),
        Ok(()) => panic!("not seen as broken: {what}"),
    }
}

#[test]
fn a_cycle_over_its_cpu_budget_is_a_violation() {
    let mut c = checker();
    let s = state(Mode::Hold);
    let budget_ns = RobotConfig::prob2_default().work_budget_ns() * DEBUG_SLOWDOWN;
    let within = Work {
        allocations: 0,
        cpu_ns: budget_ns,
    };
    assert!(c.cycle(1, &s, &[], &[], within, &[]).is_ok());
    let over = Work {
        allocations: 0,
        cpu_ns: budget_ns + 1000,
    };
    let e = c.cycle(2, &s, &[], &[], over, &[]).unwrap_err();
    let words = format!("more than its budget of {} us", budget_ns / 1000);
    assert!(e.message.contains(&words), "{e}");
    assert_eq!(c.max_work_ns, budget_ns + 1000);
}

#[test]
fn an_allocation_in_the_cycle_is_a_violation() {
    let mut c = checker();
    let s = state(Mode::Hold);
    assert!(c.cycle(1, &s, &[], &[], Work::default(), &[]).is_ok());
    let work = Work {
        allocations: 3,
        cpu_ns: 0,
    };
    let e = c.cycle(2, &s, &[], &[], work, &[]).unwrap_err();
    assert!(e.message.contains("allocated 3 times"), "{e}");
}

#[test]
fn a_number_of_the_state_that_is_not_finite_is_named() {
    let mut c = checker();
    let mut s = state(Mode::Hold);
    check(&mut c, 1, &s, &[]).unwrap();
    s.following_error[3] = f64::NAN;
    broken(check(&mut c, 2, &s, &[]), "following_error[axis 4] = NaN");
    let mut c = checker();
    let mut s = state(Mode::Hold);
    s.last_error.values[1] = f64::INFINITY;
    broken(check(&mut c, 1, &s, &[]), "last_error.values[1] = inf");
}

#[test]
fn illegal_mode_transitions_are_violations_and_legal_ones_are_not() {
    for path in [
        &[
            Mode::Hold,
            Mode::Pvt,
            Mode::Error,
            Mode::Hold,
            Mode::Calibration,
            Mode::Hold,
        ][..],
        &[
            Mode::Calibration,
            Mode::Error,
            Mode::Hold,
            Mode::VelocityControl,
        ][..],
    ] {
        let mut c = checker();
        for (k, m) in path.iter().enumerate() {
            check(&mut c, k as u64 + 1, &state(*m), &[]).unwrap();
        }
    }
    for (path, what) in [
        (&[Mode::Pvt][..], "illegal mode transition OFF -> PVT"),
        (
            &[Mode::Hold, Mode::Off][..],
            "illegal mode transition HOLD -> OFF",
        ),
        (
            &[Mode::Error, Mode::Calibration][..],
            "ERROR -> CALIBRATION",
        ),
        (
            &[Mode::Hold, Mode::Pvt, Mode::Release][..],
            "PVT -> RELEASE",
        ),
    ] {
        let mut c = checker();
        let (last, first) = path.split_last().unwrap();
        for (k, m) in first.iter().enumerate() {
            check(&mut c, k as u64 + 1, &state(*m), &[]).unwrap();
        }
        broken(check(&mut c, path.len() as u64, &state(*last), &[]), what);
    }
}

/// Seed 4848: a `hold` and a `pvt` served in the same cycle take RELEASE through HOLD to PVT,
/// and only RELEASE and PVT are published.
#[test]
fn two_transitions_through_hold_in_one_cycle_are_legal_in_that_order_only() {
    let pvt = Request::Pvt(Pvt { dt_s: 0.01 });
    let replies = [ok(1, CommandKind::Hold), ok(2, CommandKind::Pvt)];
    let run = |served: &[CommandSample], replies: &[Reply]| {
        let mut c = checker();
        c.asked(&sample(Request::Hold, 1), 1);
        c.asked(&sample(pvt, 2), 1);
        check(&mut c, 1, &state(Mode::Hold), &[]).unwrap();
        check(&mut c, 2, &state(Mode::Release), &[]).unwrap();
        check_served(&mut c, 3, &state(Mode::Pvt), replies, served)
    };
    let (hold, pvt) = (sample(Request::Hold, 1), sample(pvt, 2));
    run(&[hold, pvt], &replies).unwrap();
    let illegal = "illegal mode transition RELEASE -> PVT";
    broken(run(&[pvt, hold], &[replies[1], replies[0]]), illegal);
    broken(run(&[pvt], &replies[1..]), illegal);
    let refused = answer(1, CommandKind::Hold, Outcome::Refused(Reason::ShuttingDown));
    broken(run(&[hold, pvt], &[refused, replies[1]]), illegal);
}

#[test]
fn a_true_angle_beyond_the_mechanical_stop_is_a_violation() {
    let cfg = RobotConfig::prob2_default();
    let (_, hi) = SimBus::new(&cfg).arm().mechanical_stops(2);
    let mut c = checker();
    let mut s = state(Mode::Off);
    s.axis_flags = [0; NUM_AXES];
    s.sim_true_position[2] = hi.to_degrees() + STOP_PENETRATION_DEG - 0.01;
    s.measured_position[2] = s.sim_true_position[2];
    check(&mut c, 1, &s, &[]).unwrap();
    s.sim_true_position[2] = hi.to_degrees() + STOP_PENETRATION_DEG + 0.01;
    broken(check(&mut c, 2, &s, &[]), "axis 3: true angle");
}

#[test]
fn a_software_limit_overrun_is_a_violation_while_the_controller_is_responsible() {
    let hi = RobotConfig::prob2_default().axes[0].max_deg;
    let over = |s: &mut StateSample, q: f64| {
        s.sim_true_position[0] = q;
        s.measured_position[0] = q;
    };
    // Inside first, then beyond by more than the overrun allowed.
    let mut c = checker();
    let mut s = state(Mode::Hold);
    check(&mut c, 1, &s, &[]).unwrap();
    over(&mut s, hi + LIMIT_OVERRUN_DEG - 0.01);
    check(&mut c, 2, &s, &[]).unwrap();
    over(&mut s, hi + LIMIT_OVERRUN_DEG + 0.01);
    broken(check(&mut c, 3, &s, &[]), "beyond the software limits");
    // A push under way: the controller is not to blame, nor afterwards until back inside.
    let mut c = checker();
    let mut s = state(Mode::Hold);
    check(&mut c, 1, &s, &[]).unwrap();
    over(&mut s, hi + 5.0);
    c.cycle(2, &s, &[], &[], Work::default(), &[Fault::Push])
        .unwrap();
    check(&mut c, 3, &s, &[]).unwrap();
    over(&mut s, hi);
    check(&mut c, 4, &s, &[]).unwrap();
    over(&mut s, hi + 5.0);
    broken(check(&mut c, 5, &s, &[]), "beyond the software limits");
    // An axis calibrated while an obstacle acted (seed 124): the controller cannot know where
    // it is, so its limits are not the controller's to keep, until calibrated again.
    let (mut c, mut s) = calibrating_under_an_obstacle();
    s.mode = Mode::Hold.to_wire();
    s.axis_flags = [CALIBRATED; 6];
    check(&mut c, 2, &s, &[ok(1, CommandKind::Calibrate)]).unwrap();
    s.sim_true_position[0] = hi + 5.0;
    check(&mut c, 3, &s, &[]).unwrap();
    // A calibration search cut short at speed just inside a limit (seeds 108, 519): the axis
    // is owed its stop; once at rest inside, the limit is the controller's again.
    let mut c = checker();
    let mut s = state(Mode::Calibration);
    over(&mut s, hi - 0.5);
    s.sim_true_velocity[0] = 30.0;
    check(&mut c, 1, &s, &[]).unwrap();
    s.mode = Mode::Hold.to_wire();
    check(&mut c, 2, &s, &[]).unwrap();
    // One sample at rest inside, mid-stop, is not the end of the stop (seed 25469: the stop's
    // first set-point halted the axis for an instant).
    over(&mut s, hi - 0.2);
    s.sim_true_velocity[0] = 0.0;
    check(&mut c, 3, &s, &[]).unwrap();
    over(&mut s, hi + LIMIT_OVERRUN_DEG + 1.0);
    s.sim_true_velocity[0] = 5.0;
    check(&mut c, 4, &s, &[]).unwrap();
    // At rest inside for the cycles the measurement lags: the limit is the controller's again.
    over(&mut s, hi - 0.5);
    s.sim_true_velocity[0] = 0.0;
    let rest = c.lag_cycles as u64;
    for k in 5..5 + rest {
        check(&mut c, k, &s, &[]).unwrap();
    }
    over(&mut s, hi + LIMIT_OVERRUN_DEG + 0.01);
    broken(
        check(&mut c, 5 + rest, &s, &[]),
        "beyond the software limits",
    );
}

#[test]
fn an_axis_flagged_calibrated_off_the_truth_is_a_violation() {
    let tol = RobotConfig::prob2_default().axes[4]
        .calibration
        .tolerance_deg;
    let mut c = checker();
    let mut s = state(Mode::Hold);
    s.measured_position[4] = tol * 0.9;
    check(&mut c, 1, &s, &[]).unwrap();
    s.measured_position[4] = tol * 1.1;
    broken(check(&mut c, 2, &s, &[]), "axis 5: flagged calibrated");
    // Not flagged calibrated: the raw encoder angle may be anything.
    s.axis_flags[4] = 0;
    check(&mut c, 3, &s, &[]).unwrap();
}

#[test]
fn a_calibration_an_obstacle_or_a_push_acted_on_is_not_judged_until_calibrated_again() {
    let mut c = checker();
    let cal = sample(calibrate_all(), 1);
    c.asked(&cal, 0);
    let mut s = state(Mode::Calibration);
    s.axis_flags = [0; 6];
    c.cycle(1, &s, &[], &[], Work::default(), &[Fault::Obstacle])
        .unwrap();
    s.mode = Mode::Hold.to_wire();
    s.axis_flags = [CALIBRATED; 6];
    s.measured_position[4] = 14.9; // calibrated against the obstacle
    check(&mut c, 2, &s, &[ok(1, CommandKind::Calibrate)]).unwrap();
    check(&mut c, 3, &s, &[]).unwrap();
    // A recalibration with a free path that fails gives that calibration back: still not
    // judged.
    c.asked(&sample(calibrate_all(), 2), 3);
    s.mode = Mode::Calibration.to_wire();
    s.axis_flags = [0; 6];
    check(&mut c, 4, &s, &[]).unwrap();
    s.mode = Mode::Hold.to_wire();
    s.axis_flags = [CALIBRATED; 6];
    let aborted = answer(2, CommandKind::Calibrate, Outcome::Failed(Reason::Aborted));
    check(&mut c, 5, &s, &[aborted]).unwrap();
    check(&mut c, 6, &s, &[]).unwrap();
    // Calibrated again with a free path: judged again.
    c.asked(&sample(calibrate_all(), 3), 6);
    s.mode = Mode::Calibration.to_wire();
    s.axis_flags = [0; 6];
    check(&mut c, 7, &s, &[]).unwrap();
    s.mode = Mode::Hold.to_wire();
    s.axis_flags = [CALIBRATED; 6];
    check(&mut c, 8, &s, &[ok(3, CommandKind::Calibrate)]).unwrap();
    broken(check(&mut c, 9, &s, &[]), "axis 5: flagged calibrated");
}

#[test]
fn a_failed_attempt_under_an_obstacle_does_not_excuse_the_calibration_it_gives_back() {
    let mut c = checker();
    c.asked(&sample(calibrate_all(), 1), 0);
    let mut s = state(Mode::Calibration);
    s.axis_flags = [0; 6];
    check(&mut c, 1, &s, &[]).unwrap();
    s.mode = Mode::Hold.to_wire();
    s.axis_flags = [CALIBRATED; 6];
    check(&mut c, 2, &s, &[ok(1, CommandKind::Calibrate)]).unwrap();
    // A second attempt, under an obstacle, that fails: the free-path calibration comes back.
    c.asked(&sample(calibrate_all(), 2), 2);
    s.mode = Mode::Calibration.to_wire();
    s.axis_flags = [0; 6];
    c.cycle(3, &s, &[], &[], Work::default(), &[Fault::Obstacle])
        .unwrap();
    s.mode = Mode::Hold.to_wire();
    s.axis_flags = [CALIBRATED; 6];
    let aborted = answer(2, CommandKind::Calibrate, Outcome::Failed(Reason::Aborted));
    check(&mut c, 4, &s, &[aborted]).unwrap();
    s.measured_position[4] = 14.9;
    broken(check(&mut c, 5, &s, &[]), "axis 5: flagged calibrated");
}

#[test]
fn an_attempt_whose_searches_ended_under_an_obstacle_stays_excused_when_its_move_back_fails() {
    let (mut c, mut s) = calibrating_under_an_obstacle();
    // Every axis found its stop (one of them the obstacle): the offsets are in force, and the
    // move back trips (seed 212): the `calibrate` fails, the offsets found stay.
    s.axis_flags = [CALIBRATED; 6];
    s.measured_position[1] = -1.5;
    check(&mut c, 2, &s, &[]).unwrap();
    s.mode = Mode::Error.to_wire();
    let tripped = answer(
        1,
        CommandKind::Calibrate,
        Outcome::Failed(Reason::FollowingError {
            axis: Axis::ALL[1],
            error_deg: 24.8,
            band_deg: 2.0,
        }),
    );
    check(&mut c, 3, &s, &[tripped]).unwrap();
    check(&mut c, 4, &s, &[]).unwrap();
    // Calibrated again, with no obstacle: judged again.
    s.mode = Mode::Hold.to_wire();
    check(&mut c, 5, &s, &[]).unwrap();
    c.asked(&sample(calibrate_all(), 2), 5);
    s.mode = Mode::Calibration.to_wire();
    s.axis_flags = [0; 6];
    check(&mut c, 6, &s, &[]).unwrap();
    s.axis_flags = [CALIBRATED; 6];
    broken(check(&mut c, 7, &s, &[]), "axis 2: flagged calibrated");
}

#[test]
fn an_axis_that_brakes_beyond_its_braking_distance_or_too_long_after_a_trip_is_a_violation() {
    // Moving at 90 deg/s in VELOCITY_CONTROL, then a trip.
    let moving = |mode: Mode, q: f64, v: f64| {
        let mut s = state(mode);
        s.sim_true_position[0] = q;
        s.measured_position[0] = q;
        s.sim_true_velocity[0] = v;
        s
    };
    let mut c = checker();
    check(&mut c, 0, &state(Mode::Hold), &[]).unwrap();
    check(&mut c, 1, &moving(Mode::VelocityControl, 0.0, 90.0), &[]).unwrap();
    check(&mut c, 2, &moving(Mode::Error, 0.5, 80.0), &[]).unwrap();
    // Within the braking distance, still braking: fine; 60 deg on: beyond it.
    check(&mut c, 3, &moving(Mode::Error, 5.0, 40.0), &[]).unwrap();
    broken(
        check(&mut c, 4, &moving(Mode::Error, 60.0, 40.0), &[]),
        "travelled since the trip",
    );
    // Braking too long (still at 10 deg/s, within the distance, seconds later).
    let mut c = checker();
    check(&mut c, 0, &state(Mode::Hold), &[]).unwrap();
    check(&mut c, 1, &moving(Mode::VelocityControl, 0.0, 90.0), &[]).unwrap();
    check(&mut c, 2, &moving(Mode::Error, 0.5, 80.0), &[]).unwrap();
    broken(
        check(&mut c, 2000, &moving(Mode::Error, 10.0, 10.0), &[]),
        "its stop should have ended",
    );
    // At standstill in time: the watch ends.
    let mut c = checker();
    check(&mut c, 0, &state(Mode::Hold), &[]).unwrap();
    check(&mut c, 1, &moving(Mode::VelocityControl, 0.0, 90.0), &[]).unwrap();
    check(&mut c, 2, &moving(Mode::Error, 0.5, 80.0), &[]).unwrap();
    check(&mut c, 3, &moving(Mode::Error, 10.0, 0.0), &[]).unwrap();
    check(&mut c, 2000, &moving(Mode::Error, 10.0, 0.0), &[]).unwrap();
    // Seed 1171: an axis whose calibration an obstacle fooled is measured far off the truth;
    // the controller's picture of the arm is wrong, so the stops it makes are not judged.
    let (mut c, mut s) = calibrating_under_an_obstacle();
    s.mode = Mode::Hold.to_wire();
    s.axis_flags = [CALIBRATED; 6];
    check(&mut c, 2, &s, &[ok(1, CommandKind::Calibrate)]).unwrap();
    s.measured_position[1] = -110.0;
    s.mode = Mode::VelocityControl.to_wire();
    s.sim_true_velocity[0] = 90.0;
    check(&mut c, 3, &s, &[]).unwrap();
    s.mode = Mode::Error.to_wire();
    s.sim_true_velocity[0] = 80.0;
    check(&mut c, 4, &s, &[]).unwrap();
    s.sim_true_position[0] = 60.0;
    check(&mut c, 5, &s, &[]).unwrap();
}

/// Seed 3718: an axis a calibration search pressed 0.3 deg into its stop springs back out of
/// it after a trip, by up to the relax's band, beyond its braking distance; into the stop, or
/// further out, is still judged.
#[test]
fn an_axis_springing_out_of_the_stop_a_search_pressed_it_into_is_allowed_the_relax() {
    let lo = checker().stops_deg[2].0;
    let at = |mode: Mode, q: f64, v: f64| {
        let mut s = state(mode);
        s.axis_flags[2] = AXIS_ONLINE;
        s.sim_true_position[2] = q;
        s.measured_position[2] = q;
        s.sim_true_velocity[2] = v;
        s
    };
    let run = |to: f64| {
        let mut c = checker();
        check(&mut c, 1, &at(Mode::Calibration, lo - 0.3, 0.0), &[])?;
        check(&mut c, 2, &at(Mode::Error, lo - 0.3, 1.0), &[])?;
        check(&mut c, 3, &at(Mode::Error, to, 0.0), &[])
    };
    run(lo + 0.4).unwrap();
    broken(run(lo + 0.9), "travelled since the trip");
    // Moving deeper into the stop at the trip: no relax owed.
    let mut c = checker();
    check(&mut c, 1, &at(Mode::Calibration, lo - 0.3, 0.0), &[]).unwrap();
    check(&mut c, 2, &at(Mode::Error, lo - 0.3, -1.0), &[]).unwrap();
    broken(
        check(&mut c, 3, &at(Mode::Error, lo - 1.0, 0.0), &[]),
        "travelled since the trip",
    );
}

/// Seed 1413: while the SYNC is stuck no drive applies the controller's stop; the drive's own
/// SYNC watchdog stops the axis, and its time is allowed at the speed of the moment.
#[test]
fn a_stop_under_a_stuck_sync_is_allowed_the_drives_sync_watchdog() {
    let falling = |q: f64, v: f64| {
        let mut s = state(Mode::Error);
        s.sim_true_position[1] = q;
        s.measured_position[1] = q;
        s.sim_true_velocity[1] = v;
        s
    };
    let run = |faults: &[Fault]| {
        let mut c = checker();
        check(&mut c, 1, &state(Mode::Hold), &[])?;
        check(&mut c, 2, &falling(0.0, -10.0), &[])?;
        c.cycle(3, &falling(-3.0, -12.0), &[], &[], Work::default(), faults)
            .map_err(|v| v.message)
    };
    run(&[Fault::SyncStuck]).unwrap();
    broken(run(&[]), "travelled since the trip");
}

#[test]
fn a_reply_never_asked_for_or_given_twice_is_a_violation() {
    let mut c = checker();
    let s = state(Mode::Hold);
    c.asked(&sample(Request::Status, 1), 0);
    check(&mut c, 1, &s, &[ok(1, CommandKind::Status)]).unwrap();
    broken(
        check(&mut c, 2, &s, &[ok(1, CommandKind::Status)]),
        "never asked, or answered before",
    );
    broken(
        check(&mut c, 3, &s, &[ok(9, CommandKind::Status)]),
        "never asked, or answered before",
    );
}

#[test]
fn a_reply_of_another_kind_than_asked_is_a_violation() {
    let mut c = checker();
    let s = state(Mode::Hold);
    c.asked(&sample(Request::Status, 1), 0);
    c.asked(&sample(Request::Info, 2), 0);
    check(&mut c, 1, &s, &[ok(1, CommandKind::Status)]).unwrap();
    broken(
        check(&mut c, 2, &s, &[ok(2, CommandKind::Status)]),
        "asked kind 3, answered as kind 1",
    );
}

#[test]
fn a_sample_of_an_unknown_kind_answered_ok_is_a_violation() {
    let mut c = checker();
    let s = state(Mode::Hold);
    let unknown = CommandSample {
        kind: 99,
        client_id: CLIENT,
        request_id: 1,
        ..CommandSample::default()
    };
    c.asked(&unknown, 0);
    let mut reply = ok(1, CommandKind::Status);
    reply.kind = 99;
    let mut refused = reply;
    refused.status = 1;
    check(&mut c, 1, &s, &[refused]).unwrap();
    c.asked(
        &CommandSample {
            request_id: 2,
            ..unknown
        },
        1,
    );
    reply.request_id = 2;
    broken(
        check(&mut c, 2, &s, &[reply]),
        "of unknown kind 99 answered OK",
    );
}

#[test]
fn an_ok_that_enters_a_mode_is_published_with_that_mode() {
    let pvt = Request::Pvt(Pvt { dt_s: 0.01 });
    let mut c = checker();
    c.asked(&sample(pvt, 1), 0);
    check(&mut c, 1, &state(Mode::Hold), &[]).unwrap();
    check(&mut c, 2, &state(Mode::Pvt), &[ok(1, CommandKind::Pvt)]).unwrap();
    let mut c = checker();
    c.asked(&sample(pvt, 1), 0);
    check(&mut c, 1, &state(Mode::Hold), &[]).unwrap();
    broken(
        check(&mut c, 2, &state(Mode::Hold), &[ok(1, CommandKind::Pvt)]),
        "but the mode is HOLD, not PVT",
    );
    // Unless a later command of the cycle changed the mode again.
    let mut c = checker();
    c.asked(&sample(pvt, 1), 0);
    c.asked(&sample(Request::Hold, 2), 0);
    check(&mut c, 1, &state(Mode::Hold), &[]).unwrap();
    let replies = [ok(1, CommandKind::Pvt), ok(2, CommandKind::Hold)];
    check(&mut c, 2, &state(Mode::Hold), &replies).unwrap();
}

#[test]
fn a_refusal_says_what_was_so() {
    let pvt = Request::Pvt(Pvt { dt_s: 0.01 });
    let refused = |reason| answer(1, CommandKind::Pvt, Outcome::Refused(reason));
    let run = |before: StateSample, after: StateSample, reason| {
        let mut c = checker();
        c.asked(&sample(pvt, 1), 0);
        check(&mut c, 1, &state(Mode::Hold), &[])?;
        check(&mut c, 2, &before, &[])?;
        check(&mut c, 3, &after, &[refused(reason)])
    };
    let hold = state(Mode::Hold);
    let wrong = |mode| Reason::WrongMode { mode };
    run(
        state(Mode::Release),
        state(Mode::Release),
        wrong(Mode::Release),
    )
    .unwrap();
    broken(
        run(hold, hold, wrong(Mode::Pvt)),
        "pvt refused as not allowed in PVT, but the mode was HOLD before the cycle and HOLD after it",
    );
    let axis2 = Reason::NotCalibrated { axis: Axis::ALL[1] };
    let mut uncalibrated = hold;
    uncalibrated.axis_flags[1] = AXIS_ONLINE;
    run(hold, uncalibrated, axis2).unwrap();
    run(uncalibrated, hold, axis2).unwrap();
    broken(
        run(hold, hold, axis2),
        "refused as axis 2 not calibrated, but it was flagged calibrated",
    );
    let mut pressed = hold;
    pressed.flags = STATE_ESTOP;
    run(hold, pressed, Reason::EmergencyStop).unwrap();
    broken(
        run(hold, hold, Reason::EmergencyStop),
        "refused for the emergency stop, but it was not pressed",
    );
    // Refused, yet the mode it asks for entered.
    broken(
        run(hold, state(Mode::Pvt), Reason::Busy { remaining_s: 1.0 }),
        "but the mode went from HOLD to PVT",
    );
}

#[test]
fn a_release_of_control_served_first_may_change_the_mode_a_refusal_names() {
    // Seed 14363: the owner's `release_control` took CALIBRATION to HOLD, another client's
    // `move_all` was then refused in HOLD, and a trip took HOLD to ERROR, all in one cycle.
    let pvt = Request::Pvt(Pvt { dt_s: 0.01 });
    let run = |first: Request| {
        let mut c = checker();
        c.asked(&sample(first, 1), 0);
        c.asked(&sample(pvt, 2), 0);
        check(&mut c, 1, &state(Mode::Calibration), &[])?;
        let replies = [
            ok(1, first.kind()),
            answer(
                2,
                CommandKind::Pvt,
                Outcome::Refused(Reason::WrongMode { mode: Mode::Hold }),
            ),
        ];
        check(&mut c, 2, &state(Mode::Error), &replies)
    };
    run(Request::ReleaseControl).unwrap();
    broken(
        run(Request::TakeControl),
        "refused as not allowed in HOLD, but the mode was CALIBRATION before the cycle and ERROR after it",
    );
}

#[test]
fn an_ok_to_hold_ends_a_calibration() {
    let all = Request::Calibrate(Calibrate {
        which: Which::All,
        elbow_direction: Direction::Positive,
        wrist_direction: Direction::Positive,
        force_mechanical_stop: false,
    });
    let start = |c: &mut Checker| {
        c.asked(&sample(all, 1), 0);
        check(c, 1, &state(Mode::Hold), &[]).unwrap();
        check(c, 2, &state(Mode::Calibration), &[]).unwrap();
        c.asked(&sample(Request::Hold, 2), 2);
    };
    let mut c = checker();
    start(&mut c);
    let aborted = answer(1, CommandKind::Calibrate, Outcome::Failed(Reason::Aborted));
    let replies = [aborted, ok(2, CommandKind::Hold)];
    check(&mut c, 3, &state(Mode::Hold), &replies).unwrap();
    let mut c = checker();
    start(&mut c);
    broken(
        check(
            &mut c,
            3,
            &state(Mode::Calibration),
            &[ok(2, CommandKind::Hold)],
        ),
        "hold of client 100 request 2 answered OK (Ack) but the mode is CALIBRATION, not HOLD",
    );
    // A `calibrate` served after the `hold` in the same cycle starts a new calibration.
    let mut c = checker();
    start(&mut c);
    c.asked(&sample(all, 3), 2);
    let served = [sample(Request::Hold, 2), sample(all, 3)];
    check_served(&mut c, 3, &state(Mode::Calibration), &replies, &served).unwrap();
}

#[test]
fn an_ok_to_calibrate_needs_every_axis_it_covered_flagged_calibrated() {
    let wrist = Request::Calibrate(Calibrate {
        which: Which::Wrist,
        elbow_direction: Direction::Positive,
        wrist_direction: Direction::Positive,
        force_mechanical_stop: false,
    });
    let mut s = state(Mode::Hold);
    s.axis_flags[..3].fill(0); // axes 1 to 3 not calibrated: not covered
    let mut c = checker();
    c.asked(&sample(wrist, 1), 0);
    check(&mut c, 1, &s, &[ok(1, CommandKind::Calibrate)]).unwrap();
    s.axis_flags[4] = 0;
    let mut c = checker();
    c.asked(&sample(wrist, 1), 0);
    broken(
        check(&mut c, 1, &s, &[ok(1, CommandKind::Calibrate)]),
        "axis 5 is not flagged calibrated",
    );
    // A refusal says nothing about the axes.
    let mut c = checker();
    c.asked(&sample(wrist, 1), 0);
    let busy = Outcome::Refused(Reason::Busy { remaining_s: 1.0 });
    check(&mut c, 1, &s, &[answer(1, CommandKind::Calibrate, busy)]).unwrap();
}

#[test]
fn a_command_not_answered_in_time_is_a_violation() {
    let mut c = checker();
    let s = state(Mode::Hold);
    c.asked(&sample(Request::Status, 1), 0);
    for k in 1..=QUEUE_CYCLES {
        check(&mut c, k, &s, &[]).unwrap();
    }
    broken(
        check(&mut c, QUEUE_CYCLES + 1, &s, &[]),
        "client 100 request 1 (kind 1) sent in cycle 0 not answered",
    );
    // `hold` waits for the drives' enabling too (at least 2 s).
    let mut c = checker();
    let s = state(Mode::Off);
    c.asked(&sample(Request::Hold, 1), 0);
    for k in 1..=QUEUE_CYCLES + 400 {
        check(&mut c, k, &s, &[]).unwrap();
    }
    // `calibrate` as long as its calibration runs.
    let mut c = checker();
    c.asked(&sample(crate::stamp::calibrate_all(), 1), 0);
    let s = state(Mode::Calibration);
    for k in 1..=10_000 {
        check(&mut c, k, &s, &[]).unwrap();
    }
    broken(
        check(&mut c, 10_001, &state(Mode::Hold), &[]),
        "not answered",
    );
}

#[test]
fn a_command_left_unanswered_at_the_end_is_a_violation() {
    let mut c = checker();
    c.asked(&sample(Request::Status, 1), 0);
    c.asked(&sample(crate::stamp::calibrate_all(), 2), 0);
    let e = c.left_unanswered(3).unwrap_err();
    assert!(!e.quiet_phase);
    assert!(e.message.contains("2 commands left unanswered"), "{e}");
    let mut c = checker();
    c.asked(&sample(Request::Status, 1), 0);
    check(&mut c, 1, &state(Mode::Hold), &[ok(1, CommandKind::Status)]).unwrap();
    c.left_unanswered(1).unwrap();
}

#[test]
fn a_measurement_may_lag_the_truth_by_the_cycles_of_missed_tpdos_but_not_at_rest() {
    let cfg = RobotConfig::prob2_default();
    let tol = cfg.axes[0].calibration.tolerance_deg;
    let lag = 2.0 + f64::from(cfg.bus.max_missed_tpdos);
    let mut c = checker();
    let mut s = state(Mode::TorqueControl);
    check(&mut c, 1, &state(Mode::Hold), &[]).unwrap();
    // Fast, then braking: the measurement stale by a few cycles of the fast speed.
    s.sim_true_velocity[0] = 200.0;
    check(&mut c, 2, &s, &[]).unwrap();
    s.sim_true_velocity[0] = 50.0;
    s.measured_position[0] = 0.9 * lag * 200.0 * c.period_s;
    check(&mut c, 3, &s, &[]).unwrap();
    // At rest for as long as the measurement may lag: the tolerance alone.
    s.sim_true_velocity[0] = 0.0;
    s.measured_position[0] = tol * 0.9;
    for k in 4..4 + lag as u64 {
        check(&mut c, k, &s, &[]).unwrap();
    }
    s.measured_position[0] = tol * 1.1;
    broken(check(&mut c, 10, &s, &[]), "axis 1: flagged calibrated");
}

/// A `calibrate` of every axis asked at cycle 0 and under way at cycle 1 while an obstacle
/// acts, no axis flagged calibrated yet.
fn calibrating_under_an_obstacle() -> (Checker, StateSample) {
    let mut c = checker();
    c.asked(&sample(calibrate_all(), 1), 0);
    let mut s = state(Mode::Calibration);
    s.axis_flags = [0; 6];
    c.cycle(1, &s, &[], &[], Work::default(), &[Fault::Obstacle])
        .unwrap();
    (c, s)
}

/// A checker that has seen the arm in HOLD at cycle 0 (TORQUE_CONTROL is entered from HOLD).
fn from_hold() -> Checker {
    let mut c = checker();
    check(&mut c, 0, &state(Mode::Hold), &[]).unwrap();
    c
}

#[test]
fn a_lost_drive_s_standing_measurement_is_not_judged_and_delayed_frames_lag_longer() {
    let cfg = RobotConfig::prob2_default();
    let tol = cfg.axes[0].calibration.tolerance_deg;
    let lag = 2.0 + f64::from(cfg.bus.max_missed_tpdos);
    let mut moving = state(Mode::TorqueControl);
    moving.sim_true_velocity[0] = 100.0;
    let mut stale = moving;
    stale.measured_position[0] = tol + 1.1 * lag * 100.0 * 0.005;
    // Stale by more than the lag allows: a violation while the drive is online...
    let mut c = from_hold();
    check(&mut c, 1, &moving, &[]).unwrap();
    broken(check(&mut c, 2, &stale, &[]), "axis 1: flagged calibrated");
    // ... and not judged once the master has lost the drive (it reports nothing).
    let mut c = from_hold();
    check(&mut c, 1, &moving, &[]).unwrap();
    stale.axis_flags[0] = AXIS_CALIBRATED;
    check(&mut c, 2, &stale, &[]).unwrap();
    // While frames to the master are delayed, they may be late by DELAY_SYNCS cycles more.
    let mut c = from_hold();
    for k in 1..10 {
        check(&mut c, k, &moving, &[]).unwrap();
    }
    let late = lag + DELAY_SYNCS as f64;
    let mut s = moving;
    s.measured_position[0] = tol + 0.95 * late * 100.0 * c.period_s;
    let delayed = [Fault::BusDelay];
    assert!(c.cycle(10, &s, &[], &[], Work::default(), &delayed).is_ok());
    broken(check(&mut c, 11, &s, &[]), "axis 1: flagged calibrated");
}

/// A change that breaks a correct sample.
type Defect = fn(&mut StateSample);

#[test]
fn a_tcp_state_off_the_kinematics_of_the_reported_axes_is_a_violation() {
    let cfg = RobotConfig::prob2_default();
    let core = mcm_rt_core::cartesian::Cartesian::from_config(&cfg).unwrap();
    let moving = || {
        let mut s = state(Mode::Hold);
        s.flags = STATE_ALL_CALIBRATED;
        s.position = [10.0, -40.0, 70.0, 20.0, -60.0, 130.0];
        s.velocity = [15.0, -10.0, 25.0, 40.0, -30.0, 60.0];
        s.measured_position = s.position.map(|p| p + 0.01);
        s.sim_true_position = s.measured_position;
        core.compose(&mut s);
        s
    };
    let mut c = checker();
    check(&mut c, 1, &moving(), &[]).unwrap();
    // The same rotation written as -q is the same orientation.
    let mut s = moving();
    s.cartesian.orientation = s.cartesian.orientation.map(|x| -x);
    check(&mut c, 2, &s, &[]).unwrap();
    let cases: [(&str, Defect); 6] = [
        ("cartesian_state position", |s| {
            s.cartesian.position[0] += 1e-6
        }),
        ("cartesian_state orientation", |s| {
            let o = &mut s.cartesian.orientation;
            (o[0], o[1]) = (o[1], o[0]);
        }),
        ("cartesian_state linear_velocity", |s| {
            s.cartesian.linear_velocity = [0.0; 3];
        }),
        ("cartesian_state angular_velocity", |s| {
            s.cartesian.angular_velocity = s.cartesian.angular_velocity.map(f64::to_radians);
        }),
        // From the measured angles rather than the reported ones.
        ("cartesian_state position", |s| {
            let core =
                mcm_rt_core::cartesian::Cartesian::from_config(&RobotConfig::prob2_default())
                    .unwrap();
            s.cartesian = core.tcp_state(&s.measured_position, &s.velocity);
        }),
        ("cartesian_state absent with every axis calibrated", |s| {
            s.flags &= !STATE_CARTESIAN;
        }),
    ];
    for (k, (what, defect)) in cases.iter().enumerate() {
        let mut s = moving();
        defect(&mut s);
        broken(check(&mut checker(), k as u64 + 3, &s, &[]), what);
    }
}

#[test]
fn a_tcp_state_before_every_axis_is_calibrated_is_a_violation() {
    let mut c = checker();
    let mut s = state(Mode::Hold);
    check(&mut c, 1, &s, &[]).unwrap();
    s.flags = STATE_CARTESIAN;
    broken(check(&mut c, 2, &s, &[]), "cartesian_state present");
    let mut s = state(Mode::Hold);
    s.cartesian.position[2] = 1.0;
    broken(check(&mut checker(), 1, &s, &[]), "cartesian_state present");
}

/// `identify_payload` is answered when its procedure ends (about 20 s of moves and
/// measurements): not overdue before the bound the clients wait for it, overdue after.
#[test]
fn identify_payload_may_take_its_procedure_and_no_longer() {
    let mut c = checker();
    let s = state(Mode::Hold);
    let identify = Request::IdentifyPayload(mcm_shared::command::IdentifyPayload { apply: true });
    let period_ns = RobotConfig::prob2_default().cycle_period_ns();
    let bound = (core_reply_within(CommandKind::IdentifyPayload).as_nanos() as u64)
        .div_ceil(period_ns)
        + QUEUE_CYCLES;
    // 25 s of robot time, then its answer.
    let took = 25_000_000_000 / period_ns;
    c.asked(&sample(identify, 1), 0);
    for k in 1..took {
        check(&mut c, k, &s, &[]).unwrap();
    }
    let payload = Done::Payload(mcm_shared::reply::PayloadReply {
        mass_kg: 2.0,
        center_of_mass_m: [0.0, 0.0, 0.06],
        residual_nm: 0.1,
    });
    let done = answer(1, CommandKind::IdentifyPayload, Outcome::Done(payload));
    check(&mut c, took, &s, &[done]).unwrap();
    // One never answered is overdue once the bound has passed.
    c.asked(&sample(identify, 2), took);
    for k in took + 1..=took + bound {
        check(&mut c, k, &s, &[]).unwrap();
    }
    broken(
        check(&mut c, took + bound + 1, &s, &[]),
        "not answered by cycle",
    );
}

/// `move_linear` during motion is answered once the motion under way has stopped and the line
/// is planned: not overdue within the longest such stop, overdue after it.
#[test]
fn move_linear_may_wait_for_the_stop_before_it_and_no_longer() {
    let cfg = RobotConfig::prob2_default();
    let mut c = checker();
    let s = state(Mode::Hold);
    let line = Request::MoveLinear(mcm_shared::command::MoveLinear {
        position: [0.4, 0.0, 0.4],
        orientation: None,
        velocity: None,
        acceleration: None,
    });
    let bound =
        QUEUE_CYCLES + line_stop_ns(&cfg).div_ceil(cfg.cycle_period_ns()) + LINE_PLANNING_CYCLES;
    // The stop of an axis at full speed lasts longer than the queue's bound alone.
    assert!(bound > 2 * QUEUE_CYCLES, "{bound}");
    c.asked(&sample(line, 1), 0);
    for k in 1..=bound {
        check(&mut c, k, &s, &[]).unwrap();
    }
    broken(check(&mut c, bound + 1, &s, &[]), "not answered by cycle");
}
