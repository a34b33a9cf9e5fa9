use super::*;

/// The embedded configuration with `edit` applied to its TOML text, parsed and validated.
fn with(edit: impl Fn(&mut String)) -> Result<RobotConfig, ConfigError> {
    let mut text = PROB2_DEFAULT_TOML.to_string();
    edit(&mut text);
    RobotConfig::from_toml_str(&text)
}

/// One broken value: the edit of the valid default, then the key, value and allowed range
/// the refusal must name.
type Case = (
    fn(&mut RobotConfig),
    &'static str,
    &'static str,
    &'static str,
);

const POSITIVE: &str = "a finite value > 0";

const HB_50_50: &str = "more than the longer heartbeat period plus one cycle, \
    max(bus.drive_heartbeat_ms = 50, bus.master_heartbeat_ms = 50) + 5 ms (cycle.rate_hz = 200) \
    = 55 ms: it is the consumer time of both directions, the master's for each drive and each \
    drive's (0x1016:1) for the master";

#[rustfmt::skip]
const REFUSALS: &[Case] = &[
    // [cycle]
    (|c| c.cycle.rate_hz = 0, "cycle.rate_hz", "0", "1..=1000 Hz"),
    (|c| c.cycle.rate_hz = 1001, "cycle.rate_hz", "1001", "1..=1000 Hz"),
    (|c| c.cycle.rate_hz = 3, "cycle.rate_hz", "3",
        "a rate whose period is a whole number of nanoseconds (e.g. 100, 200, 250)"),
    (|c| c.cycle.priority = 0, "cycle.priority", "0", "1..=99 (SCHED_FIFO)"),
    (|c| c.cycle.priority = 100, "cycle.priority", "100", "1..=99 (SCHED_FIFO)"),
    (|c| c.cycle.work_budget_us = Some(0), "cycle.work_budget_us", "0",
        "1..=5000 us (above 0, at most the cycle period)"),
    (|c| c.cycle.work_budget_us = Some(5001), "cycle.work_budget_us", "5001",
        "1..=5000 us (above 0, at most the cycle period)"),
    // [bus]
    (|c| c.bus.bitrate = 0, "bus.bitrate", "0", "> 0 bit/s"),
    (|c| c.bus.load_budget = 0.0, "bus.load_budget", "0", "0 < budget <= 1"),
    (|c| c.bus.load_budget = 1.5, "bus.load_budget", "1.5", "0 < budget <= 1"),
    (|c| c.bus.load_budget = f64::NAN, "bus.load_budget", "NaN", "0 < budget <= 1"),
    (|c| c.bus.master_node_id = 0, "bus.master_node_id", "0", "1..=127"),
    (|c| c.bus.master_node_id = 128, "bus.master_node_id", "128", "1..=127"),
    (|c| c.bus.drive_heartbeat_ms = 0, "bus.drive_heartbeat_ms", "0", "> 0 ms"),
    (|c| c.bus.heartbeat_timeout_ms = 50, "bus.heartbeat_timeout_ms", "50", HB_50_50),
    (|c| c.bus.heartbeat_timeout_ms = 55, "bus.heartbeat_timeout_ms", "55", HB_50_50),
    // A drive consumer time not above the master's heartbeat period would fault the drives.
    (|c| c.bus.master_heartbeat_ms = 150, "bus.heartbeat_timeout_ms", "150",
        "more than the longer heartbeat period plus one cycle, max(bus.drive_heartbeat_ms = 50, \
         bus.master_heartbeat_ms = 150) + 5 ms (cycle.rate_hz = 200) = 155 ms: it is the consumer \
         time of both directions, the master's for each drive and each drive's (0x1016:1) for \
         the master"),
    (|c| { c.cycle.rate_hz = 400; c.bus.heartbeat_timeout_ms = 52; },
        "bus.heartbeat_timeout_ms", "52",
        "more than the longer heartbeat period plus one cycle, max(bus.drive_heartbeat_ms = 50, \
         bus.master_heartbeat_ms = 50) + 2.5 ms (cycle.rate_hz = 400) = 52.5 ms: it is the consumer \
         time of both directions, the master's for each drive and each drive's (0x1016:1) for \
         the master"),
    (|c| c.bus.master_heartbeat_ms = 0, "bus.master_heartbeat_ms", "0", "> 0 ms"),
    (|c| c.bus.sdo_timeout_ms = 0, "bus.sdo_timeout_ms", "0", "> 0 ms"),
    (|c| c.bus.boot_timeout_ms = 0, "bus.boot_timeout_ms", "0", "> 0 ms"),
    (|c| c.bus.max_missed_tpdos = 0, "bus.max_missed_tpdos", "0", ">= 1"),
    // [safety]: each bound keeps its check meaningful (docs/safety.md)
    (|c| c.safety.limit_margin_deg = -1.0, "safety.limit_margin_deg", "-1", "0..=5 deg"),
    (|c| c.safety.limit_margin_deg = f64::INFINITY, "safety.limit_margin_deg", "inf",
        "0..=5 deg"),
    (|c| c.safety.limit_margin_deg = 5.5, "safety.limit_margin_deg", "5.5", "0..=5 deg"),
    (|c| c.safety.braking_efficiency = 0.0, "safety.braking_efficiency", "0", "0.3..=1"),
    (|c| c.safety.braking_efficiency = 1.01, "safety.braking_efficiency", "1.01", "0.3..=1"),
    (|c| c.safety.reaction_cycles = 0, "safety.reaction_cycles", "0",
        "1..=100 cycles (at most 0.5 s at cycle.rate_hz = 200)"),
    (|c| c.safety.reaction_cycles = 101, "safety.reaction_cycles", "101",
        "1..=100 cycles (at most 0.5 s at cycle.rate_hz = 200)"),
    (|c| c.safety.overspeed_factor = 0.9, "safety.overspeed_factor", "0.9", "1..=1.5"),
    (|c| c.safety.overspeed_factor = 100.0, "safety.overspeed_factor", "100", "1..=1.5"),
    (|c| c.safety.overspeed_factor = f64::NAN, "safety.overspeed_factor", "NaN", "1..=1.5"),
    (|c| c.safety.release_speed_onset = 0.1, "safety.release_speed_onset", "0.1", "0.2..=0.8"),
    (|c| c.safety.release_speed_onset = 0.9, "safety.release_speed_onset", "0.9", "0.2..=0.8"),
    (|c| c.safety.release_speed_damping = 0.0, "safety.release_speed_damping", "0",
        "0.05..=0.4"),
    (|c| c.safety.release_speed_damping = f64::NAN, "safety.release_speed_damping", "NaN",
        "0.05..=0.4"),
    (|c| c.safety.flight_recorder_seconds = 0.5, "safety.flight_recorder_seconds", "0.5",
        "1..=60 s"),
    (|c| c.safety.flight_recorder_seconds = 61.0, "safety.flight_recorder_seconds", "61",
        "1..=60 s"),
    (|c| c.safety.flight_recorder_dir = " ".into(), "safety.flight_recorder_dir", "\" \"",
        "a directory path (mcm-rt creates it and checks it can write there at start)"),
    (|c| { c.bus.backend = BusBackend::Socketcan; c.bus.interface = String::new(); },
        "bus.interface", "\"\"",
        "a SocketCAN interface name (e.g. can0) when bus.backend = \"socketcan\""),
    // [[axis]] safety bounds
    (|c| c.axes[2].following_error_deg = 45.0, "axis[3].following_error_deg", "45",
        "0 < x <= 10 deg"),
    (|c| c.axes[2].max_velocity_deg_s = 500.0, "axis[3].max_velocity_deg_s", "500",
        "0 < x <= 400 deg/s"),
    (|c| c.axes[2].max_acceleration_deg_s2 = 6000.0, "axis[3].max_acceleration_deg_s2", "6000",
        "0 < x <= 5000 deg/s^2"),
    (|c| c.axes[2].max_jerk_deg_s3 = Some(1e6), "axis[3].max_jerk_deg_s3", "1000000",
        "0 < x <= 100000 deg/s^3"),
    (|c| c.axes[2].max_current_a = 16.5, "axis[3].max_current_a", "16.5",
        "0 < x <= 16 A (4 x axis[3].rated_current_a)"),
    (|c| c.axes[2].i2t_derated_current_a = 4.5, "axis[3].i2t_derated_current_a", "4.5",
        "0 < x <= 4 A (axis[3].rated_current_a: the motor must cool)"),
    (|c| c.axes[2].i2t_time_constant_s = 0.5, "axis[3].i2t_time_constant_s", "0.5", "1..=600 s"),
    (|c| c.axes[2].i2t_time_constant_s = 601.0, "axis[3].i2t_time_constant_s", "601",
        "1..=600 s"),
    (|c| c.axes[2].calibration.search_velocity_deg_s = 91.0,
        "axis[3].calibration.search_velocity_deg_s", "91",
        "0 < x <= 90 deg/s (axis[3].max_velocity_deg_s)"),
    (|c| c.axes[2].calibration.search_current_a = 10.5, "axis[3].calibration.search_current_a",
        "10.5", "0 < x <= 10 A (axis[3].max_current_a)"),
    (|c| c.axes[1].calibration.tolerance_deg = 0.05, "axis[2].calibration.tolerance_deg",
        "0.05", "0.1..=1 deg"),
    (|c| c.axes[1].calibration.tolerance_deg = 1.5, "axis[2].calibration.tolerance_deg",
        "1.5", "0.1..=1 deg"),
    (|c| c.axes[1].calibration.tolerance_deg = f64::NAN, "axis[2].calibration.tolerance_deg",
        "NaN", "0.1..=1 deg"),
    // [[axis]]
    (|c| { c.axes.pop(); }, "axis", "5", "exactly 6 [[axis]] tables"),
    (|c| c.axes[3].node_id = 0, "axis[4].node_id", "0", "1..=127"),
    (|c| c.axes[3].node_id = 128, "axis[4].node_id", "128", "1..=127"),
    (|c| c.axes[1].node_id = 1, "axis[2].node_id", "1", "a node id no other axis uses"),
    (|c| c.axes[5].node_id = 127, "axis[6].node_id", "127",
        "a node id different from bus.master_node_id"),
    (|c| c.axes[0].min_deg = 171.0, "axis[1].min_deg", "171", "below axis[1].max_deg (170)"),
    (|c| c.axes[0].min_deg = 170.0, "axis[1].min_deg", "170", "below axis[1].max_deg (170)"),
    (|c| c.axes[0].min_deg = f64::NEG_INFINITY, "axis[1].min_deg", "-inf", "a finite value"),
    (|c| c.axes[0].max_deg = f64::NAN, "axis[1].max_deg", "NaN", "a finite value"),
    (|c| c.axes[2].max_velocity_deg_s = 0.0, "axis[3].max_velocity_deg_s", "0", POSITIVE),
    (|c| c.axes[2].max_acceleration_deg_s2 = -1.0, "axis[3].max_acceleration_deg_s2", "-1",
        POSITIVE),
    (|c| c.axes[2].gear_ratio = f64::NAN, "axis[3].gear_ratio", "NaN", POSITIVE),
    (|c| c.axes[2].torque_constant_nm_a = 0.0, "axis[3].torque_constant_nm_a", "0", POSITIVE),
    (|c| c.axes[2].rated_current_a = 0.0, "axis[3].rated_current_a", "0", POSITIVE),
    (|c| c.axes[2].max_current_a = 0.0, "axis[3].max_current_a", "0", POSITIVE),
    (|c| c.axes[2].i2t_time_constant_s = f64::INFINITY, "axis[3].i2t_time_constant_s", "inf",
        POSITIVE),
    (|c| c.axes[2].i2t_derated_current_a = 0.0, "axis[3].i2t_derated_current_a", "0", POSITIVE),
    (|c| c.axes[2].armature_kg_m2 = 0.0, "axis[3].armature_kg_m2", "0", POSITIVE),
    (|c| c.axes[2].following_error_deg = 0.0, "axis[3].following_error_deg", "0", POSITIVE),
    (|c| c.axes[2].calibration.search_velocity_deg_s = 0.0,
        "axis[3].calibration.search_velocity_deg_s", "0", POSITIVE),
    (|c| c.axes[2].calibration.search_current_a = 0.0, "axis[3].calibration.search_current_a",
        "0", POSITIVE),
    (|c| c.axes[2].max_jerk_deg_s3 = Some(0.0), "axis[3].max_jerk_deg_s3", "0", POSITIVE),
    (|c| c.axes[4].gear_efficiency = 0.0, "axis[5].gear_efficiency", "0", "0 < x <= 1"),
    (|c| c.axes[4].gear_efficiency = 1.1, "axis[5].gear_efficiency", "1.1", "0 < x <= 1"),
    (|c| c.axes[4].encoder_counts_per_rev = 0, "axis[5].encoder_counts_per_rev", "0", "> 0"),
    (|c| c.axes[0].rated_current_a = 11.0, "axis[1].rated_current_a", "11",
        "<= axis[1].max_current_a (10)"),
    (|c| c.axes[0].i2t_derated_current_a = 10.5, "axis[1].i2t_derated_current_a", "10.5",
        "<= axis[1].max_current_a (10)"),
    (|c| c.axes[0].coulomb_friction_nm = -1.0, "axis[1].coulomb_friction_nm", "-1",
        "a finite value >= 0"),
    (|c| c.axes[0].viscous_friction_nm_s_rad = -0.5, "axis[1].viscous_friction_nm_s_rad", "-0.5",
        "a finite value >= 0"),
    (|c| c.axes[0].calibration.direction = 0, "axis[1].calibration.direction", "0", "+1 or -1"),
    (|c| c.axes[0].calibration.direction = 2, "axis[1].calibration.direction", "2", "+1 or -1"),
    (|c| c.axes[0].calibration.stop_deg = 170.0, "axis[1].calibration.stop_deg", "170",
        "beyond the software limit in the search direction (170 deg)"),
    (|c| c.axes[1].calibration.stop_deg = -100.0, "axis[2].calibration.stop_deg", "-100",
        "beyond the software limit in the search direction (-120 deg)"),
    (|c| c.axes[0].calibration.light_barrier_deg = Some(170.0),
        "axis[1].calibration.light_barrier_deg", "170", "inside the limits (-170, 170) deg"),
    // [arm]
    (|c| c.arm.gravity = [0.0, 0.0, f64::NAN], "arm.gravity", "[0.0, 0.0, NaN]",
        "three finite values (m/s^2)"),
    (|c| { c.arm.links.pop(); }, "arm.link", "5", "exactly 6 [[arm.link]] tables"),
    (|c| c.arm.links[2].d = f64::NAN, "arm.link[3].d", "NaN", "a finite value"),
    (|c| c.arm.links[2].a = f64::INFINITY, "arm.link[3].a", "inf", "a finite value"),
    (|c| c.arm.links[2].alpha_deg = f64::NAN, "arm.link[3].alpha_deg", "NaN", "a finite value"),
    (|c| c.arm.links[2].offset_deg = f64::NEG_INFINITY, "arm.link[3].offset_deg", "-inf",
        "a finite value"),
    (|c| c.arm.links[0].mass = 0.0, "arm.link[1].mass", "0", "> 0 kg"),
    (|c| c.arm.links[0].inertia = [1.0, 0.0, 1.0], "arm.link[1].inertia", "[1.0, 0.0, 1.0]",
        "three values > 0 kg m^2"),
    (|c| c.arm.links[5].com = [0.0, f64::NAN, 0.0], "arm.link[6].com", "[0.0, NaN, 0.0]",
        "three finite values (m)"),
    (|c| c.arm.tool.mass = -0.1, "arm.tool.mass", "-0.1", "a mass from 0 to 5 kg"),
    (|c| c.arm.tool.com = [f64::INFINITY, 0.0, 0.0], "arm.tool.com[0]", "inf",
        "a finite number"),
    (|c| c.arm.tool.com = [0.0, 0.0, 0.6], "arm.tool.com", "0.6",
        "at most 0.5 m from the flange"),
    (|c| c.arm.tool.tcp = Some(TcpConfig { position: [0.0; 3], orientation: [0.0, 0.0, 0.5, 1.0] }),
        "arm.tool.tcp.orientation", "1.11803398875",
        "a unit quaternion [x, y, z, w] (norm 1 within 0.001)"),
    (|c| c.arm.tool.inertia = Some([0.01, 0.01, 0.03, 0.0, 0.0, 0.0]), "arm.tool.inertia", "-0.005",
        "a physical inertia (positive semi-definite, triangle inequality)"),
    // [sim]
    (|c| c.sim.physics_step_us = 0, "sim.physics_step_us", "0",
        "> 0 and a divisor of the cycle period (5000 us)"),
    (|c| c.sim.physics_step_us = 3000, "sim.physics_step_us", "3000",
        "> 0 and a divisor of the cycle period (5000 us)"),
    (|c| c.sim.initial_position_deg[2] = 136.0, "sim.initial_position_deg[3]", "136",
        "within the axis limits [-135, 135] deg"),
    (|c| c.sim.initial_position_deg[0] = f64::NAN, "sim.initial_position_deg[1]", "NaN",
        "within the axis limits [-170, 170] deg"),
    (|c| c.sim.max_encoder_offset_deg = -1.0, "sim.max_encoder_offset_deg", "-1",
        "a finite value >= 0 deg"),
    (|c| c.sim.stop_stiffness_nm_rad = 0.0, "sim.stop_stiffness_nm_rad", "0",
        "a finite value > 0 Nm/rad"),
    (|c| c.sim.stop_damping_nm_s_rad = -1.0, "sim.stop_damping_nm_s_rad", "-1",
        "a finite value >= 0 Nm s/rad"),
];

#[test]
fn every_refusal_names_key_value_and_allowed_range() {
    RobotConfig::prob2_default().validate().unwrap();
    for (i, (edit, key, value, allowed)) in REFUSALS.iter().enumerate() {
        let mut cfg = RobotConfig::prob2_default();
        edit(&mut cfg);
        let err = cfg.validate().unwrap_err();
        let expected = ConfigError::Invalid {
            key: key.to_string(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        };
        assert_eq!(err, expected, "case {i} ({key})");
        assert_eq!(
            err.to_string(),
            format!("config key `{key}` = {value} is not allowed: {allowed}"),
            "case {i}"
        );
    }
}

#[rustfmt::skip]
const ACCEPTED: &[fn(&mut RobotConfig)] = &[
    |c| { c.cycle.rate_hz = 1000; c.cycle.work_budget_us = Some(1000); },
    // The reaction bound is in time: at 1 Hz one cycle is already a second.
    // (And the heartbeats, sent on cycle instants, can be a second apart.)
    |c| { c.cycle.rate_hz = 1; c.safety.reaction_cycles = 1; c.bus.heartbeat_timeout_ms = 1051; },
    |c| c.bus.heartbeat_timeout_ms = 56,
    |c| { c.bus.master_heartbeat_ms = 100; c.bus.heartbeat_timeout_ms = 106; },
    |c| c.cycle.work_budget_us = Some(5000),
    |c| c.cycle.work_budget_us = None,
    |c| c.cycle.priority = 99,
    |c| c.bus.load_budget = 1.0,
    |c| c.safety.limit_margin_deg = 0.0,
    |c| c.safety.limit_margin_deg = 5.0,
    |c| c.safety.braking_efficiency = 1.0,
    |c| c.safety.braking_efficiency = 0.3,
    |c| c.safety.reaction_cycles = 1,
    |c| c.safety.reaction_cycles = 100,
    |c| c.safety.overspeed_factor = 1.0,
    |c| c.safety.overspeed_factor = 1.5,
    |c| c.safety.release_speed_onset = 0.2,
    |c| c.safety.release_speed_onset = 0.8,
    |c| c.safety.release_speed_damping = 0.05,
    |c| c.safety.release_speed_damping = 0.4,
    |c| c.safety.flight_recorder_seconds = 60.0,
    |c| c.safety.flight_recorder_seconds = 1.0,
    |c| c.axes[2].following_error_deg = 10.0,
    |c| c.axes[2].max_current_a = 16.0,
    |c| c.axes[2].i2t_derated_current_a = 4.0,
    |c| c.axes[2].calibration.search_velocity_deg_s = 90.0,
    |c| c.axes[0].max_jerk_deg_s3 = None,
    |c| c.axes[0].calibration.light_barrier_deg = None,
    |c| c.axes[0].gear_efficiency = 1.0,
    |c| c.axes[0].rated_current_a = c.axes[0].max_current_a,
    |c| { c.axes[0].coulomb_friction_nm = 0.0; c.axes[0].viscous_friction_nm_s_rad = 0.0; },
    |c| c.arm.tool.mass = 0.0,
    |c| c.sim.initial_position_deg[0] = c.axes[0].max_deg,
    |c| c.sim.max_encoder_offset_deg = 0.0,
    |c| c.sim.stop_damping_nm_s_rad = 0.0,
];

#[test]
fn boundary_values_are_accepted() {
    for (i, edit) in ACCEPTED.iter().enumerate() {
        let mut cfg = RobotConfig::prob2_default();
        edit(&mut cfg);
        assert_eq!(cfg.validate(), Ok(()), "case {i}");
    }
}

#[test]
fn embedded_default_is_valid() {
    let cfg = RobotConfig::prob2_default();
    assert_eq!(cfg.axes.len(), NUM_AXES);
    assert_eq!(cfg.bus.backend, BusBackend::Sim);
    assert_eq!(cfg.cycle_period_ns(), 5_000_000);
    assert_eq!(cfg.cycle_period_s(), 0.005);
}

#[test]
fn axis_conversions_follow_motor_and_gear() {
    let axis = &RobotConfig::prob2_default().axes[0];
    // 0.12 Nm/A * 120 * 0.9
    assert!((axis.torque_per_amp() - 12.96).abs() < 1e-12);
    // 4096 counts * 120 motor turns per joint turn of 2 pi rad
    let per_rad = 4096.0 * 120.0 / core::f64::consts::TAU;
    assert!((axis.counts_per_rad() - per_rad).abs() < 1e-9);
}

#[test]
fn file_round_trip_equals_embedded_default() {
    let path = std::env::temp_dir().join(format!("mcm-config-test-{}.toml", std::process::id()));
    std::fs::write(&path, PROB2_DEFAULT_TOML).unwrap();
    let read = RobotConfig::from_file(&path);
    std::fs::remove_file(&path).unwrap();
    assert_eq!(read, Ok(RobotConfig::prob2_default()));
}

#[test]
fn socketcan_backend_and_candump_log_parse() {
    let cfg = with(|t| {
        *t = t.replacen(r#"backend = "sim""#, r#"backend = "socketcan""#, 1);
        *t = t.replacen("[bus]", "[bus]\ncandump_log = \"/tmp/bus.log\"", 1);
    })
    .unwrap();
    assert_eq!(cfg.bus.backend, BusBackend::Socketcan);
    assert_eq!(cfg.bus.candump_log.as_deref(), Some("/tmp/bus.log"));
}

#[test]
fn unknown_key_is_named() {
    let err = with(|t| *t = t.replacen("[cycle]", "[cycle]\nrate = 3", 1)).unwrap_err();
    let ConfigError::Parse(msg) = err else {
        panic!("{err:?}")
    };
    assert!(msg.contains("rate"), "{msg}");
}

/// The words of the backends are the ones `bus.backend` takes, and the list of them in
/// messages names each.
#[test]
fn each_backend_reads_from_its_word() {
    for b in BusBackend::ALL {
        let word = b.as_str();
        assert_eq!(word.parse::<BusBackend>(), Ok(b));
        assert!(BusBackend::WORDS.contains(&format!("`{word}`")), "{word}");
        let cfg =
            with(|t| *t = t.replacen(r#"backend = "sim""#, &format!("backend = \"{word}\""), 1));
        // (socketcan also needs an interface: refused by validate, not by the word)
        if let Err(ConfigError::Parse(msg)) = cfg {
            panic!("{word}: {msg}");
        }
    }
    assert_eq!(
        "can".parse::<BusBackend>().unwrap_err().to_string(),
        "unknown bus backend `can`; expected `sim` or `socketcan`"
    );
}

#[test]
fn unknown_backend_is_a_parse_error_naming_it() {
    let err =
        with(|t| *t = t.replacen(r#"backend = "sim""#, r#"backend = "ethercat""#, 1)).unwrap_err();
    let ConfigError::Parse(msg) = err else {
        panic!("{err:?}")
    };
    assert!(msg.contains("ethercat"), "{msg}");
}

#[test]
fn bad_value_in_the_file_is_refused_by_validate() {
    let err = with(|t| *t = t.replacen("rate_hz = 200", "rate_hz = 0", 1)).unwrap_err();
    assert_eq!(
        err.to_string(),
        "config key `cycle.rate_hz` = 0 is not allowed: 1..=1000 Hz"
    );
}

#[test]
fn missing_section_is_a_parse_error() {
    let err = with(|t| *t = t.replacen("[safety]", "[safetyx]", 1)).unwrap_err();
    assert!(matches!(err, ConfigError::Parse(_)), "{err:?}");
}

#[test]
fn missing_file_names_the_path() {
    let err = RobotConfig::from_file(Path::new("/nonexistent/robot.toml")).unwrap_err();
    let ConfigError::Read { path, reason } = &err else {
        panic!("{err:?}")
    };
    assert_eq!(path, "/nonexistent/robot.toml");
    assert_eq!(
        err.to_string(),
        format!("cannot read config file /nonexistent/robot.toml: {reason}")
    );
}

#[test]
fn the_work_budget_defaults_to_half_the_period() {
    let mut c = RobotConfig::prob2_default();
    assert_eq!(
        c.cycle.work_budget_us,
        Some(2500),
        "deploy/prob2.toml sets it"
    );
    assert_eq!(c.work_budget_ns(), 2_500_000);
    c.cycle.work_budget_us = None;
    c.cycle.rate_hz = 250;
    assert_eq!(c.work_budget_ns(), 2_000_000);
}

#[test]
fn the_tool_table_takes_a_tcp_and_an_inertia_and_defaults_to_the_flange() {
    let default = RobotConfig::prob2_default();
    let tool = default.arm.tool.active();
    assert_eq!(tool.tcp, crate::tool::Tcp::FLANGE);
    assert_eq!(tool.inertia, [0.0; 6]);
    assert_eq!((tool.mass, tool.center_of_mass), (3.8, [0.0, 0.0, 0.08]));

    let text = PROB2_DEFAULT_TOML.replace(
        "com = [0.0, 0.0, 0.08]    #",
        "com = [0.0, 0.0, 0.08]\ninertia = [0.004, 0.004, 0.002, 0.0, 0.0, 0.0]\n\
         tcp = { position = [0.0, 0.0, 0.15], orientation = [0.0, 0.0, 0.0, 1.0] }\n#",
    );
    let cfg = RobotConfig::from_toml_str(&text).unwrap();
    let tool = cfg.arm.tool.active();
    assert_eq!(tool.tcp.position, [0.0, 0.0, 0.15]);
    assert_eq!(tool.inertia, [0.004, 0.004, 0.002, 0.0, 0.0, 0.0]);
}
