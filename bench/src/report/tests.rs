use super::*;
use mcm_shared::protocol::results::Detail;
use mcm_shared::sample::StateSample;

/// The timing of a detailed status of `state`.
fn timing(state: &StateSample) -> Timing {
    Detail::from_state(state).timing
}

#[test]
fn the_latency_figures_are_the_status_timing_and_an_empty_window_has_none() {
    let mut s = StateSample::default();
    s.timing.since_start.p50_ns = 14_000;
    s.timing.since_start.p99_9_ns = 45_000;
    s.timing.since_start.max_ns = 900_000;
    let (since, recent) = rt_latency(&timing(&s));
    assert_eq!(
        (since.p50, since.p99_9, since.max),
        (Some(14.0), Some(45.0), Some(900.0))
    );
    assert_eq!(recent, None, "no cycle in the recent window");
    s.timing.recent.cycles = 2000;
    s.timing.recent.p99_9_ns = 70_000;
    assert_eq!(rt_latency(&timing(&s)).1.unwrap().p99_9, Some(70.0));
}

#[test]
fn verdicts_need_a_figure() {
    assert_eq!(Verdict::at_most(Some(1.5), 1.5), Verdict::Pass);
    assert_eq!(Verdict::at_most(Some(1.6), 1.5), Verdict::Fail);
    assert_eq!(Verdict::below(Some(150.0), 150.0), Verdict::Fail);
    assert_eq!(Verdict::at_least(Some(5000.0), 5000.0), Verdict::Pass);
    assert_eq!(Verdict::at_least(None, 1.0), Verdict::NotMeasured);
    assert_eq!(ratio(Some(3.0), Some(2.0)), Some(1.5));
    assert_eq!(ratio(Some(3.0), Some(0.0)), None);
    assert_eq!(ratio(None, Some(2.0)), None);
}

#[test]
fn tables_print_na_for_unknown_figures() {
    let rt = Latency {
        p50: Some(20.0),
        ..Latency::default()
    };
    let ct = Latency {
        p50: Some(10.0),
        max: Some(12_500.0),
        ..Latency::default()
    };
    let t = latency_table(&rt, None, Some(&ct));
    let words = |t: &str| -> Vec<String> {
        t.lines()
            .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
            .collect()
    };
    assert!(
        words(&t).contains(&"p50 20 us n/a 10 us 2.00".to_string()),
        "{t}"
    );
    assert!(
        words(&t).contains(&"p99.9 n/a n/a n/a n/a".to_string()),
        "{t}"
    );
    // With a recent window, the ratio is the recent figure's.
    let recent = Latency {
        p50: Some(30.0),
        ..Latency::default()
    };
    let t2 = latency_table(&rt, Some(&recent), Some(&ct));
    assert!(
        words(&t2).contains(&"p50 20 us 30 us 10 us 3.00".to_string()),
        "{t2}"
    );
    assert!(t.contains("12.5 ms"), "{t}");
    let rows = [
        Row::new("a", "1", "< 2", Verdict::Pass),
        Row::new("b", "n/a", "< 2", Verdict::NotMeasured),
        Row::info("c", "x"),
    ];
    let t = table(&rows);
    assert!(t.contains("targets: 1 PASS, 0 FAIL, 1 not measured"), "{t}");
    assert!(t.contains("| n/a\n"), "{t}");
}
