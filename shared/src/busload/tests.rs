use super::*;

#[test]
fn frame_sizes_match_the_reference() {
    let sizes: Vec<u32> = [0u8, 1, 2, 4, 6, 8]
        .iter()
        .map(|&s| frame_bits_worst_case(s))
        .collect();
    assert_eq!(sizes, [55, 65, 75, 95, 115, 135]);
    assert_eq!(frame_bits_unstuffed(8), 111);
    assert_eq!(frame_bits_unstuffed(0), 47);
}

#[test]
fn reference_numbers_at_1_mbit() {
    let l = BusLoad::compute(6, 250, 1_000_000, 0, 0, 0, 0.7);
    // 6 x (135 + 135) + RPDO2 105 (5 bytes) + SYNC 55.
    assert_eq!(l.rpdo2_bits, 105);
    assert_eq!(l.bits_per_cycle, 1780);
    assert!((l.cycle_bus_time_us() - 1780.0).abs() < 1e-9);
    assert!((l.load - 0.445).abs() < 1e-12, "{}", l.load);
    assert!((BusLoad::compute(6, 500, 1_000_000, 0, 0, 0, 1.0).load - 0.89).abs() < 1e-12);
    assert!((BusLoad::compute(6, 1000, 1_000_000, 0, 0, 0, 1.0).load - 1.78).abs() < 1e-12);
    // 70 % ceiling: 393 Hz.
    assert_eq!(l.max_rate_hz.floor(), 393.0);
    assert!((l.max_rate_hz - 393.26).abs() < 0.01);
    // Heartbeats of 7 nodes at 100 ms: +0.46 % of 1 Mbit/s.
    let hb = BusLoad::compute(6, 250, 1_000_000, 100, 100, 0, 0.7);
    assert!((hb.heartbeat_bits_per_s / 1e6 - 0.00455).abs() < 1e-6);
    assert_eq!(hb.heartbeat_producers, 7);
    // TPDO2 of 6 drives repeated every 100 ms: 6 x 65 bits x 10/s = 3900 bit/s, +0.39 %.
    let t2 = BusLoad::compute(6, 250, 1_000_000, 0, 0, 100, 0.7);
    assert!((t2.tpdo2_bits_per_s - 3900.0).abs() < 1e-9);
    assert!((t2.load - l.load - 0.0039).abs() < 1e-12);
    assert!((l.max_rate_hz - t2.max_rate_hz - 3900.0 / 1780.0).abs() < 1e-9);
}

#[test]
fn prob2_default_is_accepted() {
    let cfg = RobotConfig::prob2_default();
    let l = check_config(&cfg).unwrap();
    assert_eq!(l.bits_per_cycle, 1780);
    assert_eq!((l.rate_hz, l.bitrate), (200, 500_000));
    assert!((l.cycle_bus_time_us() - 3560.0).abs() < 1e-9);
    // 1780 * 200 + 65 * (6 * 20 + 20) + 65 * 6 * 10 (TPDO2 repeats) = 369000 bit/s of 500000.
    assert_eq!(l.tpdo2_period_ms, TPDO2_EVENT_TIMER_MS);
    assert!((l.load - 0.738).abs() < 1e-9, "{}", l.load);
}

#[test]
fn prob2_at_250_hz_is_refused_with_the_numbers() {
    let mut cfg = RobotConfig::prob2_default();
    cfg.cycle.rate_hz = 250;
    let err = check_config(&cfg).unwrap_err();
    assert_eq!(
        err.to_string(),
        "worst-case bus load 91.6 % exceeds bus.load_budget 80.0 %: per cycle 1780 bits \
         (6 axes x (RPDO1 135 + TPDO1 135 bits) + RPDO2 105 bits + SYNC 55 bits) = 3560 us at \
         500000 bit/s, x cycle.rate_hz 250 = 445000 bit/s, plus heartbeats 9100 bit/s \
         (7 producers x 65 bits), plus TPDO2 repeats 3900 bit/s (6 drives x 65 bits every \
         100 ms); allowed: cycle.rate_hz <= 217 Hz at this bit rate, or a higher bus.bitrate"
    );
}
