use super::*;

#[test]
fn the_same_seed_gives_the_same_stream_and_another_seed_another() {
    let a: Vec<u64> = (0..4)
        .scan(Rng::new(7), |r, _| Some(r.next_u64()))
        .collect();
    let b: Vec<u64> = (0..4)
        .scan(Rng::new(7), |r, _| Some(r.next_u64()))
        .collect();
    let c: Vec<u64> = (0..4)
        .scan(Rng::new(8), |r, _| Some(r.next_u64()))
        .collect();
    assert_eq!(a, b);
    assert_ne!(a, c);
    // SplitMix64's published first output for seed 0.
    assert_eq!(Rng::new(0).next_u64(), 0xE220_A839_7B1D_CDAF);
}

#[test]
fn unit_and_below_stay_in_range() {
    let mut r = Rng::new(1);
    for _ in 0..10_000 {
        let u = r.unit();
        assert!((0.0..1.0).contains(&u));
        assert!(r.below(3) < 3);
    }
}
