//! Scenario tests of the refusals no other scenario provokes: each command in a mode that does
//! not take it, values out of range, unreachable targets, PVT batches that break a limit or do
//! not fit, a calibration superseded by `hold`. Each checks the refusal's reason and figures and
//! the mode after it (virtual time, the whole simulated robot, as in `controller/tests.rs`).

use crate::controller::tests::{Robot, move_axis};
use mcm_shared::command::{
    Axis, Calibrate, Direction, MoveAll, Pvt, PvtChunk, PvtPoint, Request, SetTorques, SimCommand,
    TorqueControl, Which,
};
use mcm_shared::mode::Mode;
use mcm_shared::reply::{Done, Outcome, PvtQuantity, Reason, Response};

const PVT: Request = Request::Pvt(Pvt { dt_s: 0.01 });

fn calibrate(which: Which) -> Request {
    Request::Calibrate(Calibrate {
        which,
        elbow_direction: Direction::Positive,
        wrist_direction: Direction::Positive,
        force_mechanical_stop: false,
    })
}

fn torque_control() -> Request {
    Request::TorqueControl(TorqueControl {
        timeout_s: None,
        gravity_compensation: false,
    })
}

fn set_torques(torques_nm: [f64; 6]) -> Request {
    Request::SetTorques(SetTorques { torques_nm })
}

/// A chunk of PVT points all at `position_deg` with velocity `velocity_deg_s` on every axis.
fn chunk(n: usize, position_deg: f64, velocity_deg_s: f64, last: bool) -> Request {
    let p = PvtPoint {
        position_deg: [position_deg; 6],
        velocity_deg_s: [velocity_deg_s; 6],
    };
    Request::PvtPoints(PvtChunk::new(&vec![p; n], last).unwrap())
}

/// Send `req` as client 42 with request id `id` in one cycle, without waiting for its reply.
fn send(r: &mut Robot, req: Request, id: u64) {
    let mut s = req.encode();
    (s.client_id, s.request_id) = (42, id);
    r.step(&[s]);
}

/// The reply to request `id` among the replies given so far.
fn reply_to(r: &Robot, id: u64) -> Option<Response> {
    r.replies
        .iter()
        .rev()
        .find(|rep| rep.request_id == id)
        .map(|rep| Response::decode(rep).expect("a well-formed reply"))
}

#[test]
fn motion_commands_outside_their_mode_are_refused_naming_the_mode() {
    let mut r = Robot::new();
    let off = Reason::WrongMode { mode: Mode::Off };
    for req in [
        move_axis(1, 10.0),
        Request::MoveAll(MoveAll {
            targets_deg: [0.0; 6],
            velocity_factor: 0.5,
        }),
        chunk(4, 0.0, 0.0, true),
        set_torques([0.0; 6]),
        PVT,
        Request::Release,
        torque_control(),
    ] {
        assert_eq!(r.refused(req, 5), off, "{req:?}");
    }
    assert_eq!(r.mode(), Mode::Off, "nothing changed");
    // Status and info are answered in every mode.
    assert_eq!(r.ok(Request::Status, 5), Done::Ack);
    let Done::Info(info) = r.ok(Request::Info, 5) else {
        panic!("info answers with the figures")
    };
    assert_eq!(info.num_axes, 6);
    assert!((info.period_s - 0.005).abs() < 1e-12, "{info:?}");
}

#[test]
fn a_sim_command_without_the_simulators_edge_is_not_simulated() {
    // The bare cycle (no edge, as with real drives) hands a `sim` request to the controller.
    let cfg = mcm_shared::config::RobotConfig::prob2_default();
    let mut cycle = crate::cycle::Cycle::new(&cfg, mcm_sim::SimBus::new(&cfg)).unwrap();
    let mut s = Request::Sim(SimCommand {
        emergency_stop: Some(true),
        ..SimCommand::default()
    })
    .encode();
    (s.client_id, s.request_id) = (3, 30);
    cycle.run(0, &[s]);
    let reply = Response::decode(cycle.replies().last().unwrap()).unwrap();
    assert_eq!(reply.request_id, 30);
    assert_eq!(reply.outcome, Outcome::Refused(Reason::NotSimulated));
}

#[test]
fn calibrate_and_set_torques_are_refused_in_the_modes_that_do_not_take_them() {
    let mut r = Robot::calibrated();
    assert_eq!(r.ok(Request::Hold, 5), Done::Ack, "hold in HOLD is a no-op");
    assert_eq!(
        r.refused(set_torques([0.0; 6]), 5),
        Reason::WrongMode { mode: Mode::Hold }
    );
    r.ok(PVT, 5);
    assert_eq!(
        r.refused(calibrate(Which::All), 5),
        Reason::WrongMode { mode: Mode::Pvt }
    );
    assert_eq!(
        r.refused(Request::Release, 5),
        Reason::WrongMode { mode: Mode::Pvt }
    );
    r.ok(Request::Hold, 5);
    r.ok(Request::Release, 5);
    assert_eq!(
        r.refused(calibrate(Which::All), 5),
        Reason::WrongMode {
            mode: Mode::Release
        }
    );
    assert_eq!(r.mode(), Mode::Release, "the refusal changed nothing");
    r.ok(Request::Hold, 5);
    assert_eq!(r.mode(), Mode::Hold, "hold leaves RELEASE");
}

#[test]
fn a_torque_beyond_the_peak_is_refused_whole_naming_axis_and_limit() {
    let mut r = Robot::calibrated();
    r.ok(torque_control(), 5);
    let peak = r.cycle.controller().p.peak_torque[2];
    let mut t = [1.0; 6];
    t[2] = peak + 1.0;
    assert_eq!(
        r.refused(set_torques(t), 5),
        Reason::InvalidArgument {
            refusal: mcm_shared::ranges::ArgRefusal {
                arg: mcm_shared::ranges::Arg::Torques,
                axis: Some(Axis::ALL[2]),
                value: peak + 1.0,
                min: -peak,
                max: peak,
            }
        }
    );
    let crate::controller::state::State::Torque { torques, .. } = r.cycle.controller().state else {
        panic!("still in torque control: {:?}", r.mode())
    };
    assert_eq!(torques, [0.0; 6], "none of the refused torques was taken");
    assert_eq!(r.ok(set_torques([1.0; 6]), 5), Done::Ack);
    r.ok(Request::Hold, 5);
    assert_eq!(r.mode(), Mode::Hold, "hold leaves torque control");
}

#[test]
fn an_unreachable_target_is_refused_with_the_reachable_range_in_degrees() {
    let mut r = Robot::calibrated();
    r.ok(PVT, 5);
    let (min, max) = {
        let p = &r.cycle.controller().p;
        (p.reach_min[1].to_degrees(), p.reach_max[1].to_degrees())
    };
    let Reason::Unreachable {
        axis,
        target_deg,
        min_deg,
        max_deg,
    } = r.refused(move_axis(2, max + 1.0), 5)
    else {
        panic!("an unreachable refusal")
    };
    assert_eq!(axis, Axis::ALL[1]);
    assert!((target_deg - (max + 1.0)).abs() < 1e-9, "{target_deg}");
    assert!((min_deg - min).abs() < 1e-9 && (max_deg - max).abs() < 1e-9);
    // Only the axis a `move_axis` moves is checked; `move_all` checks every axis.
    let mut targets = [0.0; 6];
    targets[1] = min - 1.0;
    let reason = r.refused(
        Request::MoveAll(MoveAll {
            targets_deg: targets,
            velocity_factor: 0.5,
        }),
        5,
    );
    assert!(
        matches!(reason, Reason::Unreachable { axis, .. } if axis == Axis::ALL[1]),
        "{reason:?}"
    );
    assert_eq!(r.mode(), Mode::Pvt);
    assert!(
        !r.cycle.controller().state.planned_motion(),
        "nothing moves"
    );
}

#[test]
fn points_and_moves_while_a_move_runs_are_busy_with_the_time_left() {
    let mut r = Robot::calibrated();
    r.ok(PVT, 5);
    r.ok(move_axis(1, 30.0), 5);
    r.run(20);
    let Reason::Busy { remaining_s } = r.refused(chunk(4, 0.0, 0.0, true), 5) else {
        panic!("busy")
    };
    assert!(remaining_s > 0.1, "{remaining_s}");
    // Hold stops the move; a calibration waits for the stop to end.
    r.ok(Request::Hold, 5);
    let Reason::Busy { remaining_s } = r.refused(calibrate(Which::All), 5) else {
        panic!("busy while the stop runs")
    };
    assert!(remaining_s > 0.0, "{remaining_s}");
    // PVT entered while the stop runs carries the stop on: a move must wait for it.
    r.ok(PVT, 5);
    assert!(
        matches!(r.refused(move_axis(2, 5.0), 5), Reason::Busy { .. }),
        "the stop carried into PVT"
    );
}

#[test]
fn a_pvt_point_beyond_the_velocity_limit_refuses_the_whole_batch() {
    let mut r = Robot::calibrated();
    r.ok(PVT, 5);
    let reason = r.refused(chunk(4, 0.0, 1.0e4, true), 5);
    let Reason::PvtPoint {
        axis,
        point,
        quantity,
        value,
        limit,
    } = reason
    else {
        panic!("a point refusal: {reason:?}")
    };
    assert_eq!(
        (axis, point),
        (Axis::ALL[0], 1),
        "the first point's first axis"
    );
    assert_eq!(quantity, PvtQuantity::Velocity);
    assert!((value - 1.0e4).abs() < 1e-6 && limit < value, "{reason:?}");
    assert_eq!(r.cycle.state().pvt_queued, 0, "nothing queued");
    assert_eq!(r.mode(), Mode::Pvt);
}

#[test]
fn a_batch_longer_than_a_batch_may_be_is_refused_as_a_full_queue() {
    let mut r = Robot::calibrated();
    r.ok(PVT, 5);
    let max = crate::pvt::MAX_BATCH;
    for _ in 0..max / 4 {
        assert_eq!(r.ok(chunk(4, 0.0, 0.0, false), 5), Done::Ack);
    }
    let full = Reason::QueueFull {
        offered: max as u32 + 1,
        free: max as u32,
    };
    assert_eq!(r.refused(chunk(4, 0.0, 0.0, false), 5), full);
    // The poisoned batch stays refused up to its last chunk, which reports why.
    assert_eq!(r.refused(chunk(4, 0.0, 0.0, false), 5), full);
    assert_eq!(r.refused(chunk(4, 0.0, 0.0, true), 5), full);
    assert_eq!(r.cycle.state().pvt_queued, 0, "nothing queued");
    // The next batch starts afresh and is taken.
    assert_eq!(r.ok(chunk(4, 0.0, 0.0, true), 5), Done::Ack);
}

#[test]
fn hold_during_a_calibration_aborts_it_and_holds() {
    let mut r = Robot::new();
    send(&mut r, calibrate(Which::All), 9001);
    r.run_until("calibrating", 400, |r| r.mode() == Mode::Calibration);
    r.run(50);
    send(&mut r, Request::Hold, 9002);
    let cal = reply_to(&r, 9001).expect("the calibration is answered at once");
    assert_eq!(cal.outcome, Outcome::Failed(Reason::Aborted));
    let hold = reply_to(&r, 9002).expect("hold is answered at once");
    assert_eq!(hold.outcome, Outcome::Done(Done::Ack));
    assert_eq!(r.mode(), Mode::Hold);
    // The aborted calibration left the axes as they were: uncalibrated.
    assert_eq!(
        r.refused(PVT, 5),
        Reason::NotCalibrated { axis: Axis::ALL[0] }
    );
}

#[test]
fn a_second_hold_while_enabling_supersedes_the_first() {
    let mut r = Robot::new();
    send(&mut r, Request::Hold, 9101);
    assert_eq!(
        r.mode(),
        Mode::Off,
        "enabling reports the mode it started from"
    );
    assert!(reply_to(&r, 9101).is_none(), "not enabled yet");
    let done = r.ok(Request::Hold, 400);
    assert_eq!(done, Done::Ack);
    assert_eq!(
        reply_to(&r, 9101).map(|rep| rep.outcome),
        Some(Outcome::Failed(Reason::Aborted))
    );
    assert_eq!(r.mode(), Mode::Hold);
}

/// As on a real bus (found over SocketCAN): the switch pressed between two cycles, so that the
/// drives' EMCY 0x5441 comes in a cycle before any TPDO1 shows the input (bit 14). It is the
/// emergency stop all the same, not a drive fault.
#[test]
fn an_emcy_of_safe_torque_off_before_the_statusword_shows_it_is_the_emergency_stop() {
    use mcm_sim::SimControl;
    let mut r = Robot::calibrated();
    assert_eq!(r.mode(), Mode::Hold);
    let press = SimCommand {
        emergency_stop: Some(true),
        ..SimCommand::default()
    };
    r.cycle.bus_mut().apply(&press).unwrap();
    r.step(&[]);
    let e = r.cycle.controller().view().last_error.expect("a trip");
    assert_eq!(e.reason, Reason::EmergencyStop, "{e:?}");
    r.run(5);
    let e = r.cycle.controller().view().last_error.expect("a trip");
    assert_eq!(
        e.reason,
        Reason::EmergencyStop,
        "one trip, the emergency stop: {e:?}"
    );
}

#[test]
fn hold_and_calibrate_are_refused_while_the_emergency_stop_is_pressed() {
    let mut r = Robot::new();
    let press = |pressed| {
        Request::Sim(SimCommand {
            emergency_stop: Some(pressed),
            ..SimCommand::default()
        })
    };
    r.ok(press(true), 5);
    r.run(5);
    assert_eq!(r.refused(Request::Hold, 5), Reason::EmergencyStop);
    assert_eq!(r.refused(calibrate(Which::All), 5), Reason::EmergencyStop);
    assert_eq!(r.mode(), Mode::Off);
    r.ok(press(false), 5);
    r.run(5);
    assert_eq!(r.ok(Request::Hold, 400), Done::Ack);
}

#[test]
fn a_pvt_spacing_below_one_cycle_is_refused_naming_the_range() {
    let mut r = Robot::calibrated();
    let reason = r.refused(Request::Pvt(Pvt { dt_s: 0.001 }), 5);
    assert_eq!(
        reason.to_string(),
        "argument \"dt\" = 0.001 is not allowed; expected a number from 0.005 to 1 s (at least \
         one cycle)"
    );
    assert_eq!(r.mode(), Mode::Hold, "the refusal changed nothing");
    r.ok(Request::Pvt(Pvt { dt_s: 0.005 }), 5);
    assert_eq!(r.mode(), Mode::Pvt, "one cycle is allowed");
}
