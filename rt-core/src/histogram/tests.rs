use super::*;
use proptest::prelude::*;

#[test]
fn empty_is_zero() {
    let h = Histogram::new();
    assert_eq!(h.percentile(0.99), 0);
    assert_eq!(h.count(), 0);
}

#[test]
fn percentiles_of_a_uniform_spread() {
    let mut h = Histogram::new();
    for v in 1..=1000u64 {
        h.record(v * 1000);
    }
    let p50 = h.percentile(0.5);
    let p99 = h.percentile(0.99);
    assert!((500_000..=516_000).contains(&p50), "p50 {p50}");
    assert!((990_000..=1_000_000).contains(&p99), "p99 {p99}");
    assert_eq!(h.percentile(1.0), 1_000_000);
}

#[test]
fn huge_values_saturate_the_last_bucket() {
    let mut h = Histogram::new();
    h.record(u64::MAX);
    assert_eq!(h.max(), u64::MAX);
    assert_eq!(h.percentile(0.5), u64::MAX);
}

#[test]
fn figures_match_the_percentiles_and_resolve_the_tail() {
    let mut h = Histogram::new();
    // 10,000 cycles at 20 us, one at 80 us, one at 400 us.
    for _ in 0..9_998 {
        h.record(20_000);
    }
    h.record(80_000);
    h.record(400_000);
    let f = h.figures();
    assert_eq!(f.cycles, 10_000);
    assert_eq!(f.p50_ns, h.percentile(0.5));
    assert_eq!(f.p99_9_ns, h.percentile(0.999));
    assert!((20_000..=20_640).contains(&f.p99_9_ns), "{f:?}");
    // p99.99 is the 9,999th value: the 80 us one, within 3.2 %.
    assert!((80_000..=82_560).contains(&f.p99_99_ns), "{f:?}");
    assert_eq!(f.max_ns, 400_000);
    assert_eq!(Histogram::new().figures(), LatencyFigures::default());
}

#[test]
fn merge_adds_and_clear_forgets() {
    let mut a = Histogram::new();
    let mut b = Histogram::new();
    a.record(10);
    b.record(1_000);
    b.record(2_000);
    a.merge(&b);
    assert_eq!((a.count(), a.max()), (3, 2_000));
    a.clear();
    assert_eq!((a.count(), a.max(), a.percentile(0.5)), (0, 0, 0));
}

proptest! {
    #[test]
    fn bucket_bounds_contain_the_value(v in 0u64..(15u64 << 33)) {
        let i = Histogram::index(v);
        prop_assert!(v <= Histogram::upper(i), "v {} upper {}", v, Histogram::upper(i));
        if i > 0 {
            prop_assert!(v > Histogram::upper(i - 1));
        }
        // relative error of the bucket bound at most 1/32
        prop_assert!((Histogram::upper(i) - v) as f64 <= v as f64 / 32.0 + 1.0);
    }
}
