use super::*;

const P: u64 = 5_000_000;

#[test]
fn syncs_on_time_never_add_a_period() {
    let mut pace = Pace::new(P, 2, 0);
    for k in 1..=1000u64 {
        // Up to a period and a half late, every time.
        let now = k * P + (k % 3) * P / 2;
        pace.on_sync(now);
        assert_eq!(pace.overdue(now), 0, "period {k}");
    }
}

#[test]
fn without_syncs_the_periods_follow_the_clock_behind_by_the_grace() {
    let mut pace = Pace::new(P, 2, 0);
    let mut total = 0;
    for ms in 0..=1000u64 {
        total += pace.overdue(ms * 1_000_000);
    }
    // 200 periods due in 1 s, 2 of them within the grace.
    assert_eq!(total, 198);
    assert_eq!(pace.deadline_ns(), 1_005_000_000);
}

#[test]
fn a_stall_of_the_master_is_filled_and_a_burst_after_it_does_not_run_ahead() {
    let mut pace = Pace::new(P, 2, 0);
    for k in 1..=10u64 {
        pace.on_sync(k * P);
    }
    // The master stalls for 100 ms: 18 periods without SYNC fill it, within the grace.
    assert_eq!(pace.overdue(150 * 1_000_000), 18);
    // Then it sends its late SYNCs in a burst: the clock is re-anchored, nothing added.
    for _ in 0..20 {
        pace.on_sync(150 * 1_000_000);
        assert_eq!(pace.overdue(150 * 1_000_000), 0);
    }
    // And on time again from there.
    for k in 1..=10u64 {
        pace.on_sync(150 * 1_000_000 + k * P);
        assert_eq!(pace.overdue(150 * 1_000_000 + k * P), 0);
    }
}

#[test]
fn the_deadline_is_when_the_next_period_without_sync_is_due() {
    let mut pace = Pace::new(P, 2, 0);
    let d = pace.deadline_ns();
    assert_eq!(pace.overdue(d - 1), 0);
    assert_eq!(pace.overdue(d), 1);
}
