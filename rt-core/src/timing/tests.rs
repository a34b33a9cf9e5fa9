use super::*;

#[test]
fn a_disturbance_shows_in_the_recent_window_and_leaves_it() {
    // 10 cycles per slot, 100-cycle window, refresh every cycle.
    let mut t = Timing::new(1_000, 500, 10_000, 1);
    for _ in 0..1_000 {
        t.wake(10_000);
    }
    for _ in 0..5 {
        t.wake(900_000);
    }
    let f = t.figures(0);
    assert_eq!(f.recent.max_ns, 900_000);
    assert_eq!(f.since_start.max_ns, 900_000);
    assert_eq!(f.since_start.cycles, 1_005);
    assert!(f.recent.p99_ns >= 900_000 * 31 / 32, "{f:?}");
    assert!(f.since_start.p99_ns < 11_000, "{f:?}");
    // 100 quiet cycles later the disturbance has left the window, not the since-start.
    for _ in 0..100 {
        t.wake(10_000);
    }
    let f = t.figures(0);
    assert!(f.recent.max_ns <= 10_000, "{f:?}");
    assert_eq!(f.since_start.max_ns, 900_000);
    assert!((91..=100).contains(&f.recent.cycles), "{f:?}");
    assert_eq!(f.recent_window_ns, f.recent.cycles * 1_000);
}

#[test]
fn percentiles_are_refreshed_every_n_cycles() {
    let mut t = Timing::new(1_000, 500, 1_000_000, 4);
    t.wake(100); // the first cycle refreshes
    assert_eq!(t.figures(0).since_start.cycles, 1);
    for _ in 0..3 {
        t.wake(100);
    }
    assert_eq!(t.figures(0).since_start.cycles, 1, "not yet refreshed");
    t.wake(100);
    assert_eq!(t.figures(0).since_start.cycles, 5);
    assert_eq!(t.since_start().count(), 5);
}

#[test]
fn work_over_the_budget_is_counted() {
    let mut t = Timing::new(5_000_000, 2_500_000, 1_000_000_000, 1);
    t.work(2_500_000);
    t.work(2_500_001);
    t.work(100);
    t.work(4_000_000);
    let f = t.figures(3);
    assert_eq!(f.over_budget, 2);
    assert_eq!(f.work_max_ns, 4_000_000);
    assert_eq!(f.work_budget_ns, 2_500_000);
    assert_eq!((f.period_ns, f.overruns), (5_000_000, 3));
}
