//! Every mode's exits through the one path, [`Controller::leave`]: what each exit answers the
//! command waiting for the mode's end, and which mode results. Each mode is reached on the
//! whole simulated robot in virtual time (`controller/tests.rs`); the exit is then taken
//! directly, between two cycles, and what it answered is read from the cycle's outbox.

use super::Exit;
use crate::controller::Controller;
use crate::controller::state::{After, CalPhase, State};
use crate::controller::tests::{Robot, move_axis};
use mcm_shared::command::{
    Axis, Calibrate, Direction, Pvt, Request, SetVelocities, TorqueControl, VelocityControl, Which,
};
use mcm_shared::mode::Mode;
use mcm_shared::reply::{Done, Outcome, Reason, Response};

/// A trip's reason (a following error: the one that also relaxes its axis in ERROR).
const TRIP: Reason = Reason::FollowingError {
    axis: Axis::ALL[1],
    error_deg: 3.0,
    band_deg: 2.0,
};

/// The exits a mode that runs may take, each once (and in a calibration search a failed
/// search, [`Exit::SearchFailed`]).
const EXITS: [Exit; 5] = [
    Exit::Hold,
    Exit::OwnerGone,
    Exit::Shutdown,
    Exit::Timeout,
    Exit::Trip(TRIP),
];

/// Send `req` as request `id` of client 42 in one cycle, without waiting for its reply.
fn send(r: &mut Robot, id: u64, req: Request) {
    let mut s = req.encode();
    (s.client_id, s.request_id) = (42, id);
    r.step(&[s]);
}

/// Take the exit `why` between two cycles: the mode that results and the replies it gave.
fn take(r: &mut Robot, why: Exit) -> (Mode, Vec<Response>) {
    let before = r.cycle.controller().view().replies.replies().len();
    let c: &mut Controller = r.cycle.controller_mut();
    c.leave(why);
    let replies = c.view().replies.replies()[before..]
        .iter()
        .map(|r| Response::decode(r).expect("a well-formed reply"))
        .collect();
    (c.mode(), replies)
}

fn state(r: &Robot) -> State {
    r.cycle.controller().state
}

/// After an exit: back to HOLD at rest (a `hold` after a trip).
fn back_to_hold(r: &mut Robot) {
    if r.mode() == Mode::Error {
        r.run_until("the quick stop ends", 400, |r| !state(r).planned_motion());
        r.ok(Request::Hold, 800);
    }
    r.run_until("the stop ends", 800, |r| !state(r).planned_motion());
    assert_eq!(r.mode(), Mode::Hold);
}

/// The mode an exit of a motion mode leads to.
fn motion_exit_mode(why: Exit) -> Mode {
    if why.trips() { Mode::Error } else { Mode::Hold }
}

#[test]
fn each_exit_answers_what_its_reason_says() {
    assert_eq!(Exit::Hold.reason(), Reason::Aborted);
    assert_eq!(Exit::OwnerGone.reason(), Reason::Aborted);
    assert_eq!(Exit::Timeout.reason(), Reason::Aborted);
    assert_eq!(Exit::Shutdown.reason(), Reason::ShuttingDown);
    assert_eq!(Exit::Trip(TRIP).reason(), TRIP);
    assert_eq!(Exit::SearchFailed(TRIP).reason(), TRIP);
}

#[test]
fn the_motion_modes_end_in_hold_with_the_controlled_stop_or_in_error() {
    let mut r = Robot::calibrated();
    let modes = [
        "a PVT move",
        "PVT at rest",
        "RELEASE",
        "TORQUE_CONTROL",
        "VELOCITY_CONTROL",
    ];
    for what in modes {
        for (n, why) in EXITS.into_iter().enumerate() {
            // Moving the other way each time, so that the arm stays near where it started.
            let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
            let entry = match what {
                "a PVT move" => vec![Request::Pvt(Pvt { dt_s: 0.01 }), move_axis(1, sign * 20.0)],
                "PVT at rest" => vec![Request::Pvt(Pvt { dt_s: 0.01 })],
                "RELEASE" => vec![Request::Release],
                "TORQUE_CONTROL" => vec![Request::TorqueControl(TorqueControl {
                    timeout_s: None,
                    gravity_compensation: true,
                })],
                _ => vec![
                    Request::VelocityControl(VelocityControl { timeout_s: None }),
                    Request::SetVelocities(SetVelocities {
                        velocities_deg_s: [sign * 20.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                    }),
                ],
            };
            for req in entry {
                r.ok(req, 400);
            }
            r.run(60);
            let moving = r.fastest_true_speed() > 5.0;
            assert_eq!(moving, what == "a PVT move" || what == "VELOCITY_CONTROL");
            let (mode, replies) = take(&mut r, why);
            assert_eq!(mode, motion_exit_mode(why), "{what}, {why:?}");
            assert!(replies.is_empty(), "{what}, {why:?}: {replies:?}");
            // A moving arm stops; one at rest has (next to) nothing to stop.
            let stop_s = state(&r).remaining().unwrap_or(0.0);
            if moving {
                assert!(stop_s > 0.02, "{what}, {why:?}: a stop of {stop_s} s");
            } else {
                assert!(stop_s < 0.02, "{what}, {why:?}: a stop of {stop_s} s");
            }
            if let (State::Error { relax, .. }, Exit::Trip(_)) = (state(&r), why) {
                assert_eq!(relax[1], 20, "{what}: the axis that tripped relaxes");
            }
            back_to_hold(&mut r);
        }
    }
}

#[test]
fn a_calibration_answers_its_caller_and_its_axes_keep_the_previous_calibration() {
    let mut r = Robot::calibrated();
    let calibrate = Request::Calibrate(Calibrate {
        which: Which::Axis(Axis::ALL[1]),
        elbow_direction: Direction::Positive,
        wrist_direction: Direction::Positive,
        force_mechanical_stop: false,
    });
    let searching = EXITS.into_iter().chain([Exit::SearchFailed(TRIP)]);
    for (n, why) in searching.enumerate() {
        let previous = r.cycle.controller().offsets();
        let id = 1000 + n as u64;
        send(&mut r, id, calibrate);
        r.run(100);
        assert!(
            matches!(
                state(&r),
                State::Calibration {
                    phase: CalPhase::Search { .. },
                    ..
                }
            ),
            "{why:?}: searching"
        );
        assert_eq!(r.cycle.controller().offsets()[1], None, "searching raw");
        let (mode, replies) = take(&mut r, why);
        assert_eq!(mode, motion_exit_mode(why), "{why:?}");
        assert_eq!(replies.len(), 1, "{why:?}: {replies:?}");
        assert_eq!(replies[0].request_id, id);
        assert_eq!(replies[0].outcome, Outcome::Failed(why.reason()), "{why:?}");
        assert_eq!(r.cycle.controller().offsets(), previous, "{why:?}");
        if let Exit::SearchFailed(_) = why {
            // ERROR with the controlled stop from the measured state (what moves brakes).
            let c = r.cycle.controller();
            assert_eq!(
                c.cmd.position,
                c.measured(),
                "stopping from where the arm is"
            );
            assert_eq!(
                c.cmd.velocity,
                c.measured_velocity(),
                "and as fast as it moves"
            );
        }
        back_to_hold(&mut r);
    }
    // On its way back to zero the new calibration is in force: a `hold` keeps it.
    let id = 2000;
    send(&mut r, id, calibrate);
    r.run_until("the move back to zero", 20_000, |r| {
        matches!(
            state(r),
            State::Calibration {
                phase: CalPhase::Return(_),
                ..
            }
        )
    });
    let found = r.cycle.controller().offsets();
    assert!(found[1].is_some());
    let (mode, replies) = take(&mut r, Exit::Hold);
    assert_eq!((mode, replies.len()), (Mode::Hold, 1));
    assert_eq!(replies[0].request_id, id);
    assert_eq!(replies[0].outcome, Outcome::Failed(Reason::Aborted));
    assert_eq!(r.cycle.controller().offsets(), found);
}

#[test]
fn an_enabling_goes_on_ends_in_hold_or_falls_back_to_where_it_started() {
    let mut r = Robot::new();
    let calibrate = Request::Calibrate(Calibrate {
        which: Which::All,
        elbow_direction: Direction::Positive,
        wrist_direction: Direction::Positive,
        force_mechanical_stop: false,
    });
    // `Some(true)`: enabling for HOLD; `Some(false)`: for a calibration.
    let enabling = |r: &Robot| match state(r) {
        State::Enabling { then, .. } => Some(!matches!(then, After::Calibrate(_))),
        _ => None,
    };
    for (n, why) in EXITS.into_iter().enumerate() {
        for (req, for_hold) in [(Request::Hold, true), (calibrate, false)] {
            let id = 1000 + 10 * n as u64 + u64::from(for_hold);
            send(&mut r, id, req);
            assert_eq!(enabling(&r), Some(for_hold), "{why:?}: enabling");
            let (mode, replies) = take(&mut r, why);
            assert_eq!(
                mode,
                Mode::Off,
                "{why:?}: an enabling reports where it started"
            );
            match why {
                Exit::Hold | Exit::Timeout => {
                    assert!(replies.is_empty(), "{why:?}: {replies:?}");
                    assert_eq!(enabling(&r), Some(for_hold), "{why:?}: goes on");
                }
                Exit::OwnerGone => {
                    assert!(replies.is_empty(), "{why:?}: {replies:?}");
                    assert_eq!(enabling(&r), Some(true), "ends in HOLD, no calibration");
                    r.run_until("enabled", 800, |r| enabling(r).is_none());
                    assert_eq!(r.mode(), Mode::Hold);
                    let last = r.replies.last().map(|r| Response::decode(r).unwrap());
                    // A `hold` is done; a `calibrate` is not: nothing was calibrated.
                    let answer = if for_hold {
                        Outcome::Done(Done::Ack)
                    } else {
                        Outcome::Failed(Reason::Aborted)
                    };
                    assert_eq!(
                        last.map(|l| (l.request_id, l.outcome)),
                        Some((id, answer)),
                        "the caller is answered when the enabling ends"
                    );
                }
                Exit::Shutdown | Exit::Trip(_) | Exit::SearchFailed(_) => {
                    assert_eq!(replies.len(), 1, "{why:?}: {replies:?}");
                    assert_eq!(replies[0].request_id, id);
                    assert_eq!(replies[0].outcome, Outcome::Failed(why.reason()));
                    assert!(matches!(state(&r), State::Off), "{why:?}: back to OFF");
                }
            }
            // OFF again, every drive disabled, for the next round (a drive asked to enable
            // a cycle ago may still report enabled for a few cycles).
            r.cycle.controller_mut().state = State::Off;
            r.run(20);
            r.run_until("disabled", 400, |r| {
                r.cycle.controller().feedback().iter().all(|f| !f.enabled)
            });
        }
    }
    // From ERROR, an enabling falls back to ERROR.
    r.cycle.controller_mut().state = State::error(None);
    send(&mut r, 3000, Request::Hold);
    assert_eq!(enabling(&r), Some(true));
    let (mode, replies) = take(&mut r, Exit::Shutdown);
    assert_eq!((mode, replies.len()), (Mode::Error, 1));
    assert_eq!(replies[0].outcome, Outcome::Failed(Reason::ShuttingDown));
}

#[test]
fn off_and_error_stay_and_hold_ends_only_in_a_trip() {
    let mut r = Robot::new();
    for why in EXITS {
        let (mode, replies) = take(&mut r, why);
        assert_eq!((mode, replies.len()), (Mode::Off, 0), "OFF, {why:?}");
    }
    r.ok(Request::Hold, 800);
    for why in EXITS {
        let (mode, replies) = take(&mut r, why);
        assert!(replies.is_empty(), "HOLD, {why:?}: {replies:?}");
        assert_eq!(mode, motion_exit_mode(why), "HOLD, {why:?}");
        if mode == Mode::Error {
            for again in EXITS {
                let (mode, replies) = take(&mut r, again);
                assert_eq!((mode, replies.len()), (Mode::Error, 0), "ERROR, {again:?}");
            }
            r.ok(Request::Hold, 800);
        }
    }
}

/// Seed 318 of the simulation: a search failed while another axis still searched at full
/// speed, and ERROR commanded every axis at its measured position, at rest, with no stop: the
/// drive's position loop braked the moving axis as it happened to (3.9 deg from 22 deg/s,
/// beyond its braking distance). A failed search now brakes what moves with the controlled
/// stop from the measured state, and the axis comes to rest within its braking distance.
#[test]
fn a_search_that_fails_while_an_axis_moves_at_search_speed_stops_it_in_its_braking_distance() {
    let mut r = Robot::calibrated();
    // Axis 3's search runs from near zero towards its stop at 140 deg at 30 deg/s.
    send(
        &mut r,
        6000,
        Request::Calibrate(Calibrate {
            which: Which::Axis(Axis::ALL[2]),
            elbow_direction: Direction::Positive,
            wrist_direction: Direction::Positive,
            force_mechanical_stop: false,
        }),
    );
    r.run_until("axis 3 at search speed", 2000, |r| {
        r.cycle.state().sim_true_velocity[2].abs() > 25.0
    });
    let (from, speed) = (r.truth()[2], r.cycle.state().sim_true_velocity[2]);
    let (mode, replies) = take(&mut r, Exit::SearchFailed(TRIP));
    assert_eq!((mode, replies.len()), (Mode::Error, 1));
    let c = r.cycle.controller();
    assert!(
        (c.cmd.velocity[2].to_degrees() - speed).abs() < 5.0,
        "the stop starts at the axis's speed: commanded {} deg/s, true {speed} deg/s",
        c.cmd.velocity[2].to_degrees()
    );
    let stop_s = state(&r).remaining().expect("a stop is planned");
    // At most the braking distance as the braking check computes it at 80 % of the maximum
    // deceleration, plus 0.5 deg, and at rest within the stop's time plus 0.5 s.
    let decel = c.p.limits[2].acceleration.to_degrees();
    let allowed = speed * speed / (2.0 * 0.8 * decel) + 0.5;
    let cycles = ((stop_s + 0.5) / c.p.period).ceil() as u64;
    let mut furthest: f64 = 0.0;
    for _ in 0..cycles {
        r.step(&[]);
        furthest = furthest.max((r.truth()[2] - from).abs());
    }
    assert!(r.at_rest(), "at rest {stop_s} s + 0.5 s after the failure");
    assert!(
        furthest <= allowed,
        "axis 3 went {furthest} deg from {speed} deg/s, {allowed} deg allowed"
    );
}

/// A failed search is taken only by a calibration search: anywhere else it is a bug, which a
/// debug build asserts (a release build takes it as the trip it names).
#[test]
#[cfg(debug_assertions)]
#[should_panic(expected = "outside a calibration search")]
fn a_failed_search_outside_a_calibration_search_is_a_bug() {
    let mut r = Robot::new();
    r.ok(Request::Hold, 800);
    take(&mut r, Exit::SearchFailed(TRIP));
}

#[test]
fn outside_a_search_a_failed_search_is_a_trip_and_the_rest_are_as_they_are() {
    assert_eq!(
        Exit::SearchFailed(TRIP).outside_a_search(),
        Exit::Trip(TRIP)
    );
    for why in EXITS {
        assert_eq!(why.outside_a_search(), why);
    }
}
