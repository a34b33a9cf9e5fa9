//! The faults a script's `sim` commands put under way, as the checker is told them: from the
//! sending, until an undoing command is answered OK, in the order of the replies.

use super::*;
use mcm_shared::command::Axis;
use mcm_shared::mode::CommandKind;
use mcm_shared::reply::{Done, Reason};

const CLIENT: u64 = 100;

fn sim(cmd: SimCommand, request_id: u64) -> CommandSample {
    let mut c = Request::Sim(cmd).encode();
    (c.client_id, c.request_id) = (CLIENT, request_id);
    c
}

fn reply(request_id: u64, outcome: Outcome) -> Reply {
    Response {
        client_id: CLIENT,
        request_id,
        kind: CommandKind::Sim,
        outcome,
    }
    .encode()
}

fn ok(request_id: u64) -> Reply {
    reply(request_id, Outcome::Done(Done::Ack))
}

fn faults(u: &UnderWay) -> Vec<Fault> {
    let mut out = Vec::new();
    u.faults(&BusFaults::default(), &mut out);
    out
}

fn block(a: u8) -> SimCommand {
    SimCommand {
        block_axis: Axis::new(a),
        ..SimCommand::default()
    }
}

fn unblock(a: u8) -> SimCommand {
    SimCommand {
        unblock_axis: Axis::new(a),
        ..SimCommand::default()
    }
}

#[test]
fn a_fault_is_under_way_from_its_sending_until_its_undoing_is_answered() {
    let mut u = UnderWay::default();
    assert!(faults(&u).is_empty());
    u.sent(&sim(block(3), 1));
    assert_eq!(faults(&u), [Fault::Obstacle], "pending: under way already");
    u.answered(&[ok(1)]);
    assert_eq!(faults(&u), [Fault::Obstacle]);
    u.sent(&sim(unblock(3), 2));
    assert_eq!(
        faults(&u),
        [Fault::Obstacle],
        "the undoing not answered: still acts"
    );
    u.answered(&[ok(2)]);
    assert!(faults(&u).is_empty());
}

#[test]
fn a_refused_start_puts_nothing_under_way_and_a_refused_undoing_ends_nothing() {
    let mut u = UnderWay::default();
    u.sent(&sim(block(2), 1));
    u.answered(&[reply(1, Outcome::Refused(Reason::NotSimulated))]);
    assert!(faults(&u).is_empty());
    u.sent(&sim(block(2), 2));
    u.answered(&[ok(2)]);
    u.sent(&sim(unblock(2), 3));
    u.answered(&[reply(3, Outcome::Refused(Reason::NotSimulated))]);
    assert_eq!(faults(&u), [Fault::Obstacle]);
}

#[test]
fn commands_answered_in_one_cycle_apply_in_the_order_of_the_replies() {
    // Unblocking axis 4 then blocking it leaves it blocked; the other way round, free.
    let mut u = UnderWay::default();
    u.sent(&sim(block(4), 1));
    u.sent(&sim(unblock(4), 2));
    u.answered(&[ok(2), ok(1)]);
    assert_eq!(faults(&u), [Fault::Obstacle]);
    u.sent(&sim(block(4), 3));
    u.sent(&sim(unblock(4), 4));
    u.answered(&[ok(3), ok(4)]);
    assert!(faults(&u).is_empty());
}

#[test]
fn an_obstacle_on_one_axis_stays_while_another_is_removed() {
    let mut u = UnderWay::default();
    u.sent(&sim(block(1), 1));
    u.sent(&sim(block(5), 2));
    u.answered(&[ok(1), ok(2)]);
    u.sent(&sim(unblock(1), 3));
    u.answered(&[ok(3)]);
    assert_eq!(faults(&u), [Fault::Obstacle]);
}

#[test]
fn every_kind_of_sim_fault_and_of_bus_fault_is_named() {
    let mut u = UnderWay::default();
    let mut tau = [0.0; NUM_AXES];
    tau[2] = 5.0;
    let all = SimCommand {
        emergency_stop: Some(true),
        disconnect_axis: Axis::new(6),
        block_axis: Axis::new(1),
        external_torques_nm: Some(tau),
        power_cycle: true,
        ..SimCommand::default()
    };
    u.sent(&sim(all, 1));
    let bus = BusFaults {
        lose_tx: 0.1,
        corrupt_rx: 0.1,
        delay_rx: 0.1,
        duplicate_rx: 0.1,
        lose_heartbeats_of: Some(3),
        sync_stuck: true,
        rebooting: Some(4),
        ..BusFaults::default()
    };
    let mut out = Vec::new();
    u.faults(&bus, &mut out);
    out.sort();
    assert_eq!(out, Fault::ALL);
    // Answered: the power cycle is over; zero torques end the push, the switch released and
    // the cable back end theirs.
    u.answered(&[ok(1)]);
    assert_eq!(
        faults(&u),
        [
            Fault::EmergencyStop,
            Fault::DriveSilent,
            Fault::Obstacle,
            Fault::Push
        ]
    );
    let undo = SimCommand {
        emergency_stop: Some(false),
        reconnect_axis: Axis::new(6),
        unblock_axis: Axis::new(1),
        external_torques_nm: Some([0.0; NUM_AXES]),
        ..SimCommand::default()
    };
    u.sent(&sim(undo, 2));
    u.answered(&[ok(2)]);
    assert!(faults(&u).is_empty());
}

#[test]
fn a_sample_that_does_not_decode_as_sim_starts_nothing() {
    let mut u = UnderWay::default();
    let mut bad = sim(block(1), 1);
    bad.args[3] = 9.0; // no axis 9
    u.sent(&bad);
    let mut hold = Request::Hold.encode();
    (hold.client_id, hold.request_id) = (CLIENT, 2);
    u.sent(&hold);
    assert!(faults(&u).is_empty());
}
