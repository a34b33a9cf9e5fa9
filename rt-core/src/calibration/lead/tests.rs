//! Unit tests of the lead guard.

use super::*;

const BOUND: f64 = 0.05;
const MIN_LAG: f64 = 0.001;
const CONFIRM: u32 = 4;

#[test]
fn the_bound_is_the_band_plus_the_confirmation_at_speed() {
    // 30 deg/s, 4 cycles confirmation and 3 of latency at 200 Hz: 7 x 0.15 deg.
    let b = bound(2f64.to_radians(), -30f64.to_radians(), 4, 0.005);
    assert!((b.to_degrees() - 3.05).abs() < 1e-9, "{}", b.to_degrees());
}

#[test]
fn within_the_bound_the_target_advances() {
    let mut g = LeadGuard::default();
    for k in 0..100 {
        assert_eq!(
            g.step(BOUND, BOUND, f64::from(k), true, CONFIRM, MIN_LAG),
            Verdict::Advance
        );
    }
}

#[test]
fn beyond_the_bound_without_a_push_is_blocked() {
    let mut g = LeadGuard::default();
    let lag = 2.0 * BOUND;
    for _ in 0..CONFIRM + LATENCY_CYCLES - 1 {
        assert_eq!(
            g.step(lag, BOUND, 1.0, false, CONFIRM, MIN_LAG),
            Verdict::Stay
        );
    }
    assert_eq!(
        g.step(lag, BOUND, 1.0, false, CONFIRM, MIN_LAG),
        Verdict::Blocked(lag)
    );
}

#[test]
fn beyond_the_bound_a_push_where_the_axis_stands_is_a_contact() {
    let mut g = LeadGuard::default();
    for _ in 0..CONFIRM - 1 {
        assert_eq!(
            g.step(0.1, BOUND, 1.0, true, CONFIRM, MIN_LAG),
            Verdict::Stay
        );
    }
    assert_eq!(
        g.step(0.1, BOUND, 1.0, true, CONFIRM, MIN_LAG),
        Verdict::Contact(1.0)
    );
}

#[test]
fn a_push_while_the_axis_still_moves_is_no_contact() {
    let mut g = LeadGuard::default();
    let mut last = Verdict::Advance;
    for k in 0..CONFIRM + LATENCY_CYCLES {
        last = g.step(
            0.1,
            BOUND,
            1.0 + 0.01 * f64::from(k),
            true,
            CONFIRM,
            MIN_LAG,
        );
        assert!(!matches!(last, Verdict::Contact(_)), "{last:?}");
    }
    assert_eq!(last, Verdict::Blocked(0.1));
}

#[test]
fn an_axis_that_catches_up_searches_on() {
    let mut g = LeadGuard::default();
    for _ in 0..CONFIRM + LATENCY_CYCLES - 1 {
        assert_eq!(
            g.step(0.1, BOUND, 1.0, false, CONFIRM, MIN_LAG),
            Verdict::Stay
        );
    }
    assert_eq!(
        g.step(0.0, BOUND, 1.1, false, CONFIRM, MIN_LAG),
        Verdict::Advance
    );
    // The count starts again.
    for _ in 0..CONFIRM + LATENCY_CYCLES - 1 {
        assert_eq!(
            g.step(0.1, BOUND, 1.1, false, CONFIRM, MIN_LAG),
            Verdict::Stay
        );
    }
}
