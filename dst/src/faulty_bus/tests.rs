use super::*;
use mcm_shared::config::RobotConfig;

/// Every frame the simulated robot has for the master at power-up (its drives' boot-up
/// frames), through a faulty bus with `faults`.
fn received(faults: BusFaults) -> (Vec<Frame>, BusFaultCounts) {
    let cfg = RobotConfig::prob2_default();
    let mut bus = FaultyBus::new(SimBus::new(&cfg), Rng::new(1));
    bus.faults = faults;
    let mut out = Vec::new();
    while let Some(f) = bus.recv(0).expect("the simulated bus does not fail") {
        out.push(f);
    }
    (out, bus.counts)
}

#[test]
fn a_corrupted_frame_never_reaches_the_master_the_crc_drops_it() {
    let (clean, _) = received(BusFaults::default());
    assert!(!clean.is_empty());
    let (frames, counts) = received(BusFaults {
        corrupt_rx: 1.0,
        ..BusFaults::default()
    });
    assert_eq!(frames, [], "corrupted frames reached the master");
    assert_eq!(counts.corrupted, clean.len() as u64);
}
