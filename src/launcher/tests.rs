//! The launcher's back-off against the shared restart policy.

use super::*;

#[test]
fn backoff_follows_the_policy_to_the_cap_and_resets_after_a_healthy_run() {
    let mut b = Backoff::new();
    let quick = Duration::from_millis(50);
    let waits: Vec<_> = (0..9).map(|_| b.next(quick)).collect();
    assert_eq!(waits[0], GATEWAY_RESTART.first);
    assert_eq!(waits[1], GATEWAY_RESTART.first * 2);
    assert_eq!(waits[6], Duration::from_millis(6400));
    assert_eq!(waits[7], GATEWAY_RESTART.max);
    assert_eq!(waits[8], GATEWAY_RESTART.max);
    assert_eq!(b.next(GATEWAY_RESTART.healthy_run), GATEWAY_RESTART.first);
    assert_eq!(b.next(quick), GATEWAY_RESTART.first * 2);
}
