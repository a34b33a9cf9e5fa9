use super::*;

const MS: u64 = 1_000_000;

#[test]
fn timeout_is_detected_at_exactly_the_configured_time() {
    let mut hb = HeartbeatConsumer::new(150 * MS);
    assert!(
        !hb.check(10_000 * MS),
        "not armed before the first heartbeat"
    );
    hb.on_heartbeat(1000 * MS, NmtState::PreOperational);
    hb.on_heartbeat(1050 * MS, NmtState::Operational);
    assert_eq!(hb.state(), Some(NmtState::Operational));
    assert!(hb.is_fresh(1050 * MS + 150 * MS - 1));
    assert!(!hb.check(1050 * MS + 150 * MS - 1));
    assert!(!hb.is_fresh(1200 * MS));
    assert!(hb.check(1200 * MS));
    assert!(hb.is_timed_out());
    assert!(!hb.check(1300 * MS), "reported once");
    hb.on_heartbeat(1400 * MS, NmtState::Operational);
    assert!(!hb.is_timed_out());
    assert!(hb.check(1550 * MS), "re-armed by the next heartbeat");
}

#[test]
fn arm_gives_a_grace_period_of_one_timeout() {
    let mut hb = HeartbeatConsumer::new(150 * MS);
    hb.arm(500 * MS);
    assert!(!hb.check(649 * MS));
    assert!(hb.check(650 * MS));
    hb.reset();
    assert!(!hb.check(10_000 * MS));
}

#[test]
fn producer_sends_on_its_period_grid() {
    let mut p = HeartbeatProducer::new(127, 50 * MS);
    let sent: Vec<u64> = (0..40u64)
        .map(|k| k * 5 * MS)
        .filter(|&t| p.poll(t).is_some())
        .collect();
    assert_eq!(sent, vec![0, 50 * MS, 100 * MS, 150 * MS]);
    assert_eq!(p.poll(200 * MS).unwrap().to_string(), "77F#05");
    // Missed calls: one frame, then back on the grid.
    assert!(p.poll(420 * MS).is_some());
    assert!(p.poll(440 * MS).is_none());
    assert!(p.poll(450 * MS).is_some());
}
