use super::*;
use mcm_shared::mode::CommandKind;
use mcm_shared::reply::{Done, Reason};

fn reply(request_id: u64, cycle: u64, outcome: Outcome) -> Reply {
    let mut r = Response {
        client_id: 7,
        request_id,
        kind: CommandKind::SetTorques,
        outcome,
    }
    .encode();
    r.cycle = cycle;
    r
}

#[test]
fn answers_applied_in_the_next_cycle_count_as_on_time() {
    let mut t = Tracker::default();
    t.sent(1, 100);
    t.sent(2, 101);
    t.sent(3, 102);
    assert_eq!(t.answered(&reply(1, 101, Outcome::Done(Done::Ack))), None);
    assert_eq!(t.answered(&reply(2, 103, Outcome::Done(Done::Ack))), None);
    let refused = Outcome::Refused(Reason::WrongMode { mode: Mode::Hold });
    let r = t.answered(&reply(3, 103, refused)).expect("a refusal");
    assert_eq!(r.outcome, refused);
    assert_eq!((t.answered, t.on_time, t.late), (3, 2, 1));
    // A reply twice (or to a command the ring forgot) is not counted again.
    t.answered(&reply(1, 101, Outcome::Done(Done::Ack)));
    assert_eq!(t.answered, 3);
}

#[test]
fn the_summary_says_the_share_on_time() {
    let s = ControlSummary {
        cycles: 10_000,
        missed: 2,
        sent: 10_000,
        on_time: 9_995,
        late: 5,
        unanswered: 0,
    };
    assert!((s.on_time_percent() - 99.95).abs() < 1e-9);
    assert_eq!(
        s.to_string(),
        "10000 cycles, 2 missed, 10000 commands sent, applied in the next cycle 9995/10000 (99.95 %), 0 unanswered"
    );
}
