use super::*;

const MS: u64 = 1_000_000;

#[test]
fn no_stream_has_nothing_to_join() {
    let s = Stream::default();
    assert!(!s.is_alive());
    assert_eq!(s.join(5 * MS), None);
    assert_eq!(s.elapsed_s(5 * MS), 0.0);
}

#[test]
fn time_counts_from_one_period_before_the_queuing_cycle() {
    let mut s = Stream::default();
    s.sent(10, 0.005, [1.0; NUM_AXES], [0.5; NUM_AXES]);
    assert!(s.is_alive() && s.origin_ns().is_none());
    // Before the first batch's reply the start is not known: the points all lie ahead.
    assert!((s.ahead_s(100 * MS) - 0.05).abs() < 1e-12);
    s.started(100 * MS, 5 * MS);
    assert_eq!(s.origin_ns(), Some(95 * MS));
    // A second call (later replies) does not move the start.
    s.started(105 * MS, 5 * MS);
    assert_eq!(s.origin_ns(), Some(95 * MS));
    assert!((s.elapsed_s(120 * MS) - 0.025).abs() < 1e-12);
    assert!((s.ahead_s(120 * MS) - 0.025).abs() < 1e-12);
}

#[test]
fn a_new_trajectory_joins_where_the_points_sent_end_while_they_lie_ahead() {
    let mut s = Stream::default();
    s.sent(4, 0.005, [0.1; NUM_AXES], [0.2; NUM_AXES]);
    s.started(0, 0);
    s.sent(4, 0.005, [0.3; NUM_AXES], [0.4; NUM_AXES]);
    let (begin, p, v) = s.join(10 * MS).expect("points ahead");
    assert!((begin - 0.04).abs() < 1e-12);
    assert_eq!((p, v), ([0.3; NUM_AXES], [0.4; NUM_AXES]));
    // Once the arm has passed the last point sent there is nothing to join.
    assert_eq!(s.join(40 * MS), None);
    s.end();
    assert!(!s.is_alive());
}
