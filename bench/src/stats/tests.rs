use super::*;

#[test]
fn nearest_rank_percentiles() {
    let v: Vec<u32> = (1..=1000).collect();
    assert_eq!(percentile(&v, 50.0), Some(500));
    assert_eq!(percentile(&v, 99.0), Some(990));
    assert_eq!(percentile(&v, 99.9), Some(999));
    assert_eq!(percentile(&v, 100.0), Some(1000));
    assert_eq!(percentile(&v, 0.01), Some(1));
    // Few samples: the tail percentiles are the maximum.
    assert_eq!(percentile(&[3, 7, 9], 99.9), Some(9));
    assert_eq!(percentile(&[3, 7, 9], 50.0), Some(7));
    assert_eq!(percentile::<u32>(&[], 50.0), None);
    assert_eq!(percentile(&[1], 0.0), None);
    assert_eq!(percentile(&[1], 101.0), None);
}

#[test]
fn summary_sorts_and_averages() {
    let d: Vec<Duration> = [400u64, 100, 300, 200]
        .iter()
        .map(|&us| Duration::from_micros(us))
        .collect();
    let s = Summary::of(&d).unwrap();
    assert_eq!(s.count, 4);
    assert_eq!(s.p50_us, 200.0);
    assert_eq!(s.p99_us, 400.0);
    assert_eq!(s.max_us, 400.0);
    assert_eq!(s.mean_us, 250.0);
    assert_eq!(Summary::of(&[]), None);
}

#[test]
fn histogram_percentiles() {
    // 90 samples of 10 µs, 9 of 20 µs, 1 of 40 µs.
    let mut b = vec![0u64; 50];
    b[10] = 90;
    b[20] = 9;
    b[40] = 1;
    assert_eq!(hist_percentile(&b, 0, 50.0), Some(HistFigure::Us(10)));
    assert_eq!(hist_percentile(&b, 0, 90.0), Some(HistFigure::Us(10)));
    assert_eq!(hist_percentile(&b, 0, 99.0), Some(HistFigure::Us(20)));
    assert_eq!(hist_percentile(&b, 0, 99.9), Some(HistFigure::Us(40)));
    // Overflowed samples are beyond the last bucket.
    assert_eq!(
        hist_percentile(&b, 100, 99.0),
        Some(HistFigure::Beyond { limit: 50 })
    );
    assert_eq!(hist_percentile(&b, 100, 25.0), Some(HistFigure::Us(10)));
    assert_eq!(hist_percentile(&[0, 0], 0, 50.0), None);
}
