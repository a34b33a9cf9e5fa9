use super::*;
use mcm_shared::command::Axis;
use mcm_shared::mode::{CommandKind, Mode};
use mcm_shared::reply::{Done, Outcome, Reason, Response, SafetyError};
use mcm_shared::sample::REPLIES_PER_CYCLE;

/// The kinematics of the P-Rob2, as the core builds them at start.
fn prob2() -> Cartesian {
    Cartesian::from_config(&mcm_shared::config::RobotConfig::prob2_default()).unwrap()
}

fn ack(request_id: u64) -> mcm_shared::sample::Reply {
    Response {
        client_id: 1,
        request_id,
        kind: CommandKind::Status,
        outcome: Outcome::Done(Done::Ack),
    }
    .encode()
}

#[test]
fn truth_sets_the_sim_fields_and_none_clears_them() {
    let view = CycleView::default();
    let mut s = StateSample::default();
    let truth = mcm_shared::simulator::SimTruth {
        position: [0.5; 6],
        velocity: [-1.0; 6],
        emergency_stop: true,
    };
    compose(&mut s, &view, Some(truth), &CycleClock::default(), &prob2());
    assert_eq!(s.flags, STATE_SIMULATED | STATE_SIM_ESTOP);
    assert!((s.sim_true_position[5] - 0.5f64.to_degrees()).abs() < 1e-12);
    assert!((s.sim_true_velocity[0] + 1f64.to_degrees()).abs() < 1e-12);
    compose(&mut s, &view, None, &CycleClock::default(), &prob2());
    assert_eq!(s.flags, 0);
    assert_eq!(s.sim_true_position, [0.0; 6]);
    assert_eq!(s.sim_true_velocity, [0.0; 6]);
}

#[test]
fn timing_and_flags_come_from_the_clock_and_the_view() {
    let mut view = CycleView {
        mode: Mode::Pvt,
        estop: true,
        pvt_starved: true,
        pvt_queued: 7,
        pvt_capacity: 100,
        ..CycleView::default()
    };
    view.axes[2].calibrated = true;
    view.axes[2].derated = true;
    let clock = CycleClock {
        t_ns: 42,
        timing: CycleTiming {
            period_ns: 5,
            overruns: 2,
            since_start: mcm_shared::sample::LatencyFigures {
                p99_ns: 9,
                ..Default::default()
            },
            work_max_ns: 11,
            ..CycleTiming::default()
        },
        not_realtime: true,
        command_receive_errors: 3,
        ..CycleClock::default()
    };
    let mut s = StateSample::default();
    compose(&mut s, &view, None, &clock, &prob2());
    assert_eq!(s.t_ns, 42);
    assert_eq!(
        s.flags,
        STATE_ESTOP | STATE_PVT_STARVED | STATE_NOT_REALTIME
    );
    assert_eq!(s.axis_flags[2], AXIS_CALIBRATED | AXIS_I2T_DERATED);
    assert_eq!((s.pvt_queued, s.pvt_capacity), (7, 100));
    assert_eq!(s.command_receive_errors, 3);
    assert_eq!(
        (
            s.timing.overruns,
            s.timing.since_start.p99_ns,
            s.timing.work_max_ns
        ),
        (2, 9, 11)
    );
}

#[test]
fn replies_are_counted_and_a_new_error_is_stamped_once() {
    let mut view = CycleView::default();
    let mut s = StateSample::default();
    view.replies.push(ack(1));
    view.replies.push(ack(2));
    view.last_error = Some(SafetyError {
        seq: 1,
        cycle: 4,
        unix_ns: 0,
        reason: Reason::NotCalibrated { axis: Axis::ALL[0] },
    });
    let clock = CycleClock {
        unix_ns: 1000,
        ..CycleClock::default()
    };
    compose(&mut s, &view, None, &clock, &prob2());
    assert_eq!(s.reply_head, 2);
    assert_eq!(first_reply_seq(&s, &view), 1);
    assert_eq!((s.last_error.seq, s.last_error.unix_ns), (1, 1000));
    // Next cycle: no replies, the same error; the stamp stays.
    view.replies.clear();
    let later = CycleClock {
        unix_ns: 2000,
        ..CycleClock::default()
    };
    compose(&mut s, &view, None, &later, &prob2());
    assert_eq!(s.reply_head, 2);
    assert_eq!(s.last_error.unix_ns, 1000);
    // More replies than a cycle may give: the head counts them all, the kept ones are the
    // newest and numbered last (the dropped ones leave a gap readers see).
    for n in 0..REPLIES_PER_CYCLE as u64 + 3 {
        view.replies.push(ack(100 + n));
    }
    compose(&mut s, &view, None, &later, &prob2());
    assert_eq!(s.reply_head, 2 + REPLIES_PER_CYCLE as u64 + 3);
    assert_eq!(first_reply_seq(&s, &view), 2 + 3 + 1);
    assert_eq!(view.replies.replies()[0].request_id, 103);
}

#[test]
fn bus_counters_are_published_as_the_view_has_them() {
    let view = CycleView {
        bus: mcm_shared::sample::BusCounters {
            bad_frames: 3,
            frames_dropped: 4,
            events_dropped: 5,
            bus_errors: 6,
        },
        ..CycleView::default()
    };
    let mut s = StateSample::default();
    compose(&mut s, &view, None, &CycleClock::default(), &prob2());
    assert_eq!(s.bus, view.bus);
}
