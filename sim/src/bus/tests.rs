//! Whole-bus tests of the simulated P-Rob2 with the real arm model: a scripted master
//! ([`crate::test_master`]) configures the six drives exactly as `docs/drive-profile.md` says,
//! enables them in CSP and streams targets; the truth of the arm is checked.

use super::{SYNC_ID, SimBus};
use crate::cia402::State;
use crate::drive::{EMCY_BASE, EMCY_SYNC_LOSS, SYNC_LOSS_PERIODS};
use crate::test_master::TestMaster;
use crate::{SimCommand, SimCommandError, SimControl, SimTruth};
use mcm_shared::command::Axis;

/// The axis at a 0-based index.
fn ax(index: usize) -> Axis {
    Axis::from_index(index).unwrap()
}
use mcm_bus::{Bus, Frame};
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;

const DEG: f64 = core::f64::consts::PI / 180.0;

/// The P-Rob2 configuration at a pose, without brakes (the brake test adds its own).
fn cfg_at(pose_deg: [f64; NUM_AXES]) -> RobotConfig {
    let mut cfg = RobotConfig::prob2_default();
    for a in &mut cfg.axes {
        a.brake = false;
    }
    cfg.sim.initial_position_deg = pose_deg;
    cfg.validate().unwrap();
    cfg
}

fn apply(bus: &mut SimBus, cmd: SimCommand) {
    bus.apply(&cmd).unwrap();
}

/// Boot, configure and enable every drive in CSP holding its position. With `block`, rigid
/// obstacles hold every axis where it is until the drives are enabled (the P-Rob2 has no
/// brakes, so the arm would otherwise sag during the ~40 configuration cycles).
fn enabled(cfg: &RobotConfig, block: bool) -> (SimBus, TestMaster) {
    let mut bus = SimBus::new(cfg);
    let mut m = TestMaster::new(cfg);
    for axis in (0..NUM_AXES).filter(|_| block) {
        apply(
            &mut bus,
            SimCommand {
                block_axis: Some(ax(axis)),
                ..SimCommand::default()
            },
        );
    }
    let cycles = m.run_until_enabled(&mut bus, 100);
    assert!(cycles < 60, "{cycles} cycles to enable");
    for axis in (0..NUM_AXES).filter(|_| block) {
        apply(
            &mut bus,
            SimCommand {
                unblock_axis: Some(ax(axis)),
                ..SimCommand::default()
            },
        );
    }
    for n in &m.nodes {
        assert!(
            n.aborts.is_empty(),
            "node {}: aborts {:X?}",
            n.node,
            n.aborts
        );
        assert_eq!((n.boot_ups, n.mode_display), (1, 8), "node {}", n.node);
    }
    (bus, m)
}

/// The joint angle [rad] the master's current target of `axis` means.
fn target_angle(cfg: &RobotConfig, bus: &SimBus, m: &TestMaster, axis: usize) -> f64 {
    let offset = bus.drive(axis).unwrap().encoder_offset_counts();
    (i64::from(m.nodes[axis].target) - offset) as f64 / cfg.axes[axis].counts_per_rad()
}

/// Run `cycles` master cycles, returning the truth after each SYNC.
fn run(bus: &mut SimBus, m: &mut TestMaster, cycles: usize) -> Vec<SimTruth> {
    (0..cycles)
        .map(|_| {
            m.run_cycle(bus);
            bus.truth()
        })
        .collect()
}

/// Largest |truth - target| per axis over `truths` [deg].
fn max_error_deg(truths: &[SimTruth], target: &[f64; NUM_AXES]) -> [f64; NUM_AXES] {
    core::array::from_fn(|i| {
        truths
            .iter()
            .map(|t| (t.position[i] - target[i]).abs() / DEG)
            .fold(0.0, f64::max)
    })
}

#[test]
fn whole_bus_boot_configure_enable_and_hold_still_for_2_s() {
    let cfg = RobotConfig::prob2_default();
    let (mut bus, mut m) = enabled(&cfg, false);
    let hold: [f64; NUM_AXES] = core::array::from_fn(|i| target_angle(&cfg, &bus, &m, i));
    let tpdos_before: Vec<u64> = m.nodes.iter().map(|n| n.tpdos).collect();
    let truths = run(&mut bus, &mut m, 400);
    for (n, before) in m.nodes.iter().zip(tpdos_before) {
        assert_eq!(
            n.tpdos - before,
            400,
            "one TPDO1 per SYNC from node {}",
            n.node
        );
        assert!(
            n.is_enabled() && n.emcy.is_empty(),
            "node {}: {:04X} {:?}",
            n.node,
            n.statusword,
            n.emcy
        );
    }
    let all = max_error_deg(&truths, &hold);
    let settled = max_error_deg(&truths[200..], &hold);
    let last = truths.last().unwrap();
    eprintln!("hold at {hold:?}: max error {all:?} deg, last second {settled:?} deg");
    for i in 0..NUM_AXES {
        assert!(all[i] < 0.5, "axis {}: {} deg", i + 1, all[i]);
        assert!(settled[i] < 0.05, "axis {}: {} deg", i + 1, settled[i]);
        assert!(
            last.velocity[i].abs() < 0.01 * DEG,
            "axis {}: {} rad/s",
            i + 1,
            last.velocity[i]
        );
    }
}

#[test]
fn holds_any_pose_with_the_full_tool_within_0_05_deg() {
    let poses = [
        [0.0, 90.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, -90.0, 0.0, 0.0, 90.0, 0.0],
        [30.0, 60.0, -90.0, 45.0, 90.0, -45.0],
        [-120.0, 45.0, 90.0, -150.0, -110.0, 160.0],
        [90.0, 115.0, -130.0, 90.0, 45.0, 0.0],
    ];
    for pose in poses {
        let cfg = cfg_at(pose);
        let (mut bus, mut m) = enabled(&cfg, true);
        let hold: [f64; NUM_AXES] = core::array::from_fn(|i| target_angle(&cfg, &bus, &m, i));
        let truths = run(&mut bus, &mut m, 400);
        let all = max_error_deg(&truths, &hold);
        let settled = max_error_deg(&truths[200..], &hold);
        eprintln!("pose {pose:?}: max error {all:.3?} deg, last second {settled:.4?} deg");
        for i in 0..NUM_AXES {
            assert!(all[i] < 0.5, "pose {pose:?} axis {}: {} deg", i + 1, all[i]);
            assert!(
                settled[i] < 0.05,
                "pose {pose:?} axis {}: {} deg",
                i + 1,
                settled[i]
            );
        }
    }
}

#[test]
fn follows_a_30_deg_s_ramp_with_small_lag() {
    let cfg = cfg_at([0.0, 45.0, 45.0, 0.0, 45.0, 0.0]);
    let (mut bus, mut m) = enabled(&cfg, true);
    run(&mut bus, &mut m, 100);
    let step: Vec<i32> = (0..NUM_AXES)
        .map(|i| (30.0 * DEG * cfg.cycle_period_s() * cfg.axes[i].counts_per_rad()).round() as i32)
        .collect();
    let mut lag = [0.0f64; NUM_AXES];
    for k in 0..300 {
        for (n, s) in m.nodes.iter_mut().zip(&step) {
            n.target += if k < 200 { *s } else { 0 };
        }
        m.run_cycle(&mut bus);
        // the target sent in this cycle is the set-point at the end of this SYNC period
        let truth = bus.truth();
        for (i, l) in lag.iter_mut().enumerate() {
            let e = (truth.position[i] - target_angle(&cfg, &bus, &m, i)).abs() / DEG;
            if (20..200).contains(&k) || k >= 280 {
                *l = l.max(e);
            }
        }
    }
    eprintln!("30 deg/s ramp: max lag {lag:.4?} deg");
    for (i, l) in lag.iter().enumerate() {
        assert!(
            *l < 0.15,
            "axis {}: lag {l} deg (one cycle at 30 deg/s is 0.15 deg)",
            i + 1
        );
    }
}

/// One run of a scripted scenario with fault injections: the frames sent, the frames
/// received and the truth (as bits) after every SYNC.
type Run = (Vec<Frame>, Vec<Frame>, Vec<[u64; 12]>);

fn bits(t: &SimTruth) -> [u64; 12] {
    core::array::from_fn(|i| {
        if i < 6 {
            t.position[i].to_bits()
        } else {
            t.velocity[i - 6].to_bits()
        }
    })
}

/// Fault injections of the determinism scenario, applied before the given cycle.
fn scenario_commands() -> Vec<(u64, SimCommand)> {
    let push = SimCommand {
        external_torques_nm: Some([5.0, -20.0, 8.0, 1.0, -2.0, 0.5]),
        ..SimCommand::default()
    };
    vec![
        (60, push),
        (
            90,
            SimCommand {
                external_torques_nm: Some([0.0; 6]),
                block_axis: Some(ax(2)),
                ..SimCommand::default()
            },
        ),
        (
            100,
            SimCommand {
                emergency_stop: Some(true),
                unblock_axis: Some(ax(2)),
                ..SimCommand::default()
            },
        ),
        (
            110,
            SimCommand {
                emergency_stop: Some(false),
                disconnect_axis: Some(ax(4)),
                ..SimCommand::default()
            },
        ),
        (
            150,
            SimCommand {
                reconnect_axis: Some(ax(4)),
                power_cycle: true,
                ..SimCommand::default()
            },
        ),
    ]
}

fn scenario_with_master() -> Run {
    let cfg = cfg_at([10.0, 60.0, -30.0, 20.0, 45.0, 0.0]);
    let mut bus = SimBus::new(&cfg);
    let mut m = TestMaster::new(&cfg);
    let commands = scenario_commands();
    let mut truth = Vec::new();
    for cycle in 0..250 {
        for (_, c) in commands.iter().filter(|(at, _)| *at == cycle) {
            bus.apply(c).unwrap();
        }
        for n in m.nodes.iter_mut() {
            n.reset_faults = true;
            n.target += 30; // keep moving slowly once enabled
        }
        m.run_cycle(&mut bus);
        truth.push(bits(&bus.truth()));
    }
    (m.sent, m.received, truth)
}

/// Replay exactly the frames `sent` (and the same fault injections) on a fresh bus.
fn replay(sent: &[Frame]) -> Run {
    let cfg = cfg_at([10.0, 60.0, -30.0, 20.0, 45.0, 0.0]);
    let mut bus = SimBus::new(&cfg);
    let commands = scenario_commands();
    let (mut received, mut truth, mut syncs) = (Vec::new(), Vec::new(), 0u64);
    let mut applied = 0;
    // the master drains the queue at the start of each cycle; so does the replay
    while let Some(f) = bus.recv(0).unwrap() {
        received.push(f);
    }
    for f in sent {
        while applied < commands.len() && commands[applied].0 == syncs {
            bus.apply(&commands[applied].1).unwrap();
            applied += 1;
        }
        bus.send(f).unwrap();
        if f.id == 0x080 {
            syncs += 1;
            truth.push(bits(&bus.truth()));
            while let Some(f) = bus.recv(0).unwrap() {
                received.push(f);
            }
        }
    }
    (sent.to_vec(), received, truth)
}

#[test]
fn deterministic_same_frames_sent_give_the_same_frames_and_truth_bit_for_bit() {
    let (sent, received, truth) = scenario_with_master();
    let (sent2, received2, truth2) = scenario_with_master();
    assert_eq!(sent, sent2);
    assert_eq!(received, received2);
    assert_eq!(truth, truth2);
    let (_, received3, truth3) = replay(&sent);
    // the master's last drain happens in a cycle that was never run: compare the common part
    assert_eq!(&received3[..received.len()], &received[..]);
    assert_eq!(truth3, truth);
    // the scenario did something: EMCYs of the emergency stop, boot-ups of the power cycle
    let count = |id_base: u16, first: u8| {
        received
            .iter()
            .filter(|f| f.id & !0x7F == id_base && f.data[0] == first)
            .count()
    };
    assert_eq!(count(0x080, 0x41), 6, "six EMCY 0x5441");
    assert_eq!(
        count(0x700, 0x00) - 6,
        6,
        "six boot-ups after the power cycle"
    );
}

#[test]
fn emergency_stop_faults_all_drives_and_blocks_enabling_until_released() {
    let cfg = RobotConfig::prob2_default();
    let (mut bus, mut m) = enabled(&cfg, false);
    apply(
        &mut bus,
        SimCommand {
            emergency_stop: Some(true),
            ..SimCommand::default()
        },
    );
    assert!(bus.truth().emergency_stop);
    run(&mut bus, &mut m, 2);
    for n in &mut m.nodes {
        assert_eq!(n.emcy, [0x5441], "node {}", n.node);
        assert!(n.is_fault(), "node {}: {:04X}", n.node, n.statusword);
        assert_eq!(
            n.statusword & 0x4010,
            0x4000,
            "bit 14 set, bit 4 clear: {:04X}",
            n.statusword
        );
        n.reset_faults = true;
    }
    run(&mut bus, &mut m, 20);
    for n in &m.nodes {
        assert_eq!(n.emcy, [0x5441, 0x0000], "fault reset while pressed");
        assert_eq!(
            n.statusword & 0x4F,
            0x40,
            "stays SWITCH ON DISABLED: {:04X}",
            n.statusword
        );
        assert_eq!(n.controlword, 0x06, "the master asked for shutdown");
    }
    for i in 0..NUM_AXES {
        assert_eq!(bus.drive(i).unwrap().current_a(), 0.0);
    }
    apply(
        &mut bus,
        SimCommand {
            emergency_stop: Some(false),
            ..SimCommand::default()
        },
    );
    assert!(!bus.truth().emergency_stop);
    run(&mut bus, &mut m, 6);
    assert!(
        m.nodes
            .iter()
            .all(|n| n.is_enabled() && n.statusword & 0x4010 == 0x0010),
        "{:?}",
        m.states()
    );
}

#[test]
fn a_disconnected_drive_goes_silent_and_faults_on_the_lost_master_heartbeat() {
    let cfg = RobotConfig::prob2_default();
    let (mut bus, mut m) = enabled(&cfg, false);
    let before: Vec<u64> = m.nodes.iter().map(|n| n.tpdos).collect();
    apply(
        &mut bus,
        SimCommand {
            disconnect_axis: Some(ax(2)),
            ..SimCommand::default()
        },
    );
    run(&mut bus, &mut m, 40);
    for (i, n) in m.nodes.iter().enumerate() {
        let got = n.tpdos - before[i];
        assert_eq!(got, if i == 2 { 1 } else { 40 }, "node {}", n.node); // the first cycle reads the last TPDO
    }
    assert_eq!(
        bus.drive(2).unwrap().state(),
        crate::cia402::State::Fault,
        "its heartbeat consumer fired"
    );
    assert!(
        m.nodes[2].emcy.is_empty(),
        "the EMCY was lost on the cut cable"
    );
    for i in 0..NUM_AXES {
        let c = bus.drive(i).unwrap().counters();
        let timeouts = u64::from(i == 2);
        assert_eq!(
            (c.heartbeat_timeouts, c.rpdo1_missing, c.sdo_aborts),
            (timeouts, 0, 0),
            "node {}: {c:?}",
            i + 1
        );
    }
    assert!(
        m.nodes
            .iter()
            .enumerate()
            .all(|(i, n)| i == 2 || n.is_enabled())
    );
    apply(
        &mut bus,
        SimCommand {
            reconnect_axis: Some(ax(2)),
            ..SimCommand::default()
        },
    );
    run(&mut bus, &mut m, 2);
    assert!(m.nodes[2].is_fault(), "{:04X}", m.nodes[2].statusword);
    assert_eq!(
        bus.drive(2).unwrap().od().raw(crate::od::ERROR_CODE),
        0x8130
    );
}

#[test]
fn the_drives_count_a_sync_without_its_setpoint_and_an_aborted_sdo() {
    let cfg = RobotConfig::prob2_default();
    let (mut bus, mut m) = enabled(&cfg, false);
    run(&mut bus, &mut m, 10);
    assert!(
        (0..NUM_AXES).all(|i| bus.drive(i).unwrap().counters() == Default::default()),
        "nothing lost while the master streams"
    );
    // A SYNC the master's RPDO1s did not precede: every enabled drive misses its setpoint.
    bus.send(&Frame::new(SYNC_ID, &[]).unwrap()).unwrap();
    // An SDO upload of an object node 4 does not have (0x1234:0).
    bus.send(&Frame::new(0x604, &[0x40, 0x34, 0x12, 0, 0, 0, 0, 0]).unwrap())
        .unwrap();
    for i in 0..NUM_AXES {
        let c = bus.drive(i).unwrap().counters();
        assert_eq!(c.rpdo1_missing, 1, "node {}: {c:?}", i + 1);
        assert_eq!(c.sdo_aborts, u64::from(i == 3), "node {}: {c:?}", i + 1);
        assert_eq!(c.heartbeat_timeouts, 0, "node {}: {c:?}", i + 1);
    }
}

#[test]
fn power_cycle_reboots_every_drive_with_new_offsets_and_the_master_reconfigures() {
    let cfg = RobotConfig::prob2_default();
    let (mut bus, mut m) = enabled(&cfg, false);
    let offsets: Vec<i64> = (0..NUM_AXES)
        .map(|i| bus.drive(i).unwrap().encoder_offset_counts())
        .collect();
    let positions: Vec<i32> = m.nodes.iter().map(|n| n.position).collect();
    let tpdos: Vec<u64> = m.nodes.iter().map(|n| n.tpdos).collect();
    apply(
        &mut bus,
        SimCommand {
            power_cycle: true,
            ..SimCommand::default()
        },
    );
    run(&mut bus, &mut m, 3);
    for (i, n) in m.nodes.iter().enumerate() {
        assert_eq!(n.boot_ups, 2, "node {}", n.node);
        assert_eq!(
            n.tpdos,
            tpdos[i] + 1,
            "no TPDO after the reboot: the mapping is gone (node {})",
            n.node
        );
        assert_ne!(bus.drive(i).unwrap().encoder_offset_counts(), offsets[i]);
    }
    m.run_until_enabled(&mut bus, 100);
    for (i, n) in m.nodes.iter().enumerate() {
        let shift = i64::from(n.position) - i64::from(positions[i]);
        let offset_change = bus.drive(i).unwrap().encoder_offset_counts() - offsets[i];
        assert!(
            (shift - offset_change).abs() < 50,
            "node {}: position moved with the new offset",
            n.node
        );
        assert!(n.aborts.is_empty());
    }
}

#[test]
fn sim_commands_are_validated_and_a_refused_one_changes_nothing() {
    let cfg = RobotConfig::prob2_default();
    let mut bus = SimBus::new(&cfg);
    let nan = SimCommand {
        emergency_stop: Some(true),
        external_torques_nm: Some([0.0, 0.0, 0.0, f64::NAN, 0.0, 0.0]),
        ..SimCommand::default()
    };
    let err = bus.apply(&nan).unwrap_err();
    assert!(matches!(
        err,
        SimCommandError::TorqueNotFinite { index: 3, .. }
    ));
    assert_eq!(
        err.to_string(),
        "sim: external_torques[3] = NaN is not finite"
    );
    assert!(!bus.truth().emergency_stop, "nothing applied");
    assert!(bus.recv(0).unwrap().is_some(), "boot-ups queued");
}

#[test]
fn external_push_is_rejected_by_the_integral_and_a_blocked_axis_saturates_the_current() {
    let cfg = cfg_at([0.0, 90.0, 0.0, 0.0, 0.0, 0.0]);
    let (mut bus, mut m) = enabled(&cfg, true);
    run(&mut bus, &mut m, 100);
    let hold: [f64; NUM_AXES] = core::array::from_fn(|i| target_angle(&cfg, &bus, &m, i));
    apply(
        &mut bus,
        SimCommand {
            external_torques_nm: Some([0.0, 20.0, 0.0, 0.0, 0.0, 0.0]),
            ..SimCommand::default()
        },
    );
    let pushed = run(&mut bus, &mut m, 200);
    let err = max_error_deg(&pushed, &hold);
    let settled = max_error_deg(&pushed[100..], &hold);
    assert!(
        err[1] > 0.005 && err[1] < 0.5 && settled[1] < 0.05,
        "{err:?} {settled:?}"
    );
    apply(
        &mut bus,
        SimCommand {
            external_torques_nm: Some([0.0; 6]),
            block_axis: Some(ax(0)),
            ..SimCommand::default()
        },
    );
    let q0 = bus.truth().position[0];
    let step = (2.0 * DEG * cfg.axes[0].counts_per_rad()) as i32;
    m.nodes[0].target += step; // 2 deg away, against the obstacle
    run(&mut bus, &mut m, 100);
    // the obstacle is a stiff spring (sim.stop_stiffness_nm_rad): 129.6 Nm deflect it ~0.37 deg
    let pressed = (bus.truth().position[0] - q0).abs() / DEG;
    assert!(pressed < 0.5, "held by the obstacle: {pressed} deg");
    assert_eq!(
        m.nodes[0].current, 2500,
        "current at the 0x6073 limit (per-mille of rated)"
    );
    m.nodes[0].target -= step;
    apply(
        &mut bus,
        SimCommand {
            unblock_axis: Some(ax(0)),
            ..SimCommand::default()
        },
    );
    let released = run(&mut bus, &mut m, 200);
    let err = max_error_deg(&released[100..], &hold);
    assert!(err[0] < 0.05, "no wind-up after the block: {err:?}");
}

#[test]
fn brakes_hold_a_disabled_axis_and_release_when_enabled() {
    let mut cfg = cfg_at([0.0, 90.0, 0.0, 0.0, 0.0, 0.0]);
    cfg.axes[1].brake = true;
    let mut bus = SimBus::new(&cfg);
    let mut m = TestMaster::new(&cfg);
    for n in &mut m.nodes {
        n.enable = false;
    }
    let q0 = bus.truth().position;
    run(&mut bus, &mut m, 60);
    let q = bus.truth().position;
    assert!(
        (q[1] - q0[1]).abs() < 0.01 * DEG,
        "the braked shoulder holds: {}",
        (q[1] - q0[1]) / DEG
    );
    assert!((q[2] - q0[2]).abs() > 1.0 * DEG, "the unbraked elbow falls");
    assert!(bus.drive(1).unwrap().brake_engaged());
    for n in &mut m.nodes {
        n.enable = true;
    }
    m.run_until_enabled(&mut bus, 20);
    assert!(!bus.drive(1).unwrap().brake_engaged());
}

#[test]
fn light_barrier_bit_15_shows_the_positive_side() {
    for (base_deg, set) in [(10.0, true), (-10.0, false)] {
        let mut bus = SimBus::new(&cfg_at([base_deg, 0.0, 0.0, 0.0, 0.0, 0.0]));
        bus.send(&Frame::new(0x080, &[]).unwrap()).unwrap();
        let sw =
            |axis: usize| bus.drive(axis).unwrap().od().raw(crate::od::STATUSWORD) & 0x8000 != 0;
        assert_eq!(sw(0), set, "base at {base_deg} deg, barrier at 0 deg");
        assert!(!sw(1), "the shoulder has no light barrier");
    }
}

#[test]
fn receive_queue_is_a_bounded_ring_that_counts_overruns() {
    let mut bus = SimBus::new(&RobotConfig::prob2_default());
    assert_eq!(bus.now_ns(), 0);
    let read = Frame::new(0x601, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]).unwrap();
    for _ in 0..600 {
        bus.send(&read).unwrap();
    }
    assert_eq!(bus.rx_overruns(), 6 + 600 - super::RX_CAPACITY as u64);
    let mut n = 0;
    while bus.recv(u64::MAX).unwrap().is_some() {
        n += 1;
    }
    assert_eq!(n, super::RX_CAPACITY);
    bus.send(&Frame::new(0x080, &[]).unwrap()).unwrap();
    assert_eq!(bus.now_ns(), 5_000_000);
}

/// Store the calibration 12345 in drive 3 (node 3) by SDO; the receive queue must be empty
/// (between SYNCs: only the answers queue).
fn store_calibration_12345_in_node_3(bus: &mut SimBus) {
    for req in [
        [0x23, 0x00, 0x21, 0x01, 0x39, 0x30, 0x00, 0x00], // 0x2100:1 = 12345
        [0x2F, 0x00, 0x21, 0x02, 0x01, 0x00, 0x00, 0x00], // 0x2100:2 = 1
    ] {
        bus.send(&Frame::new(0x603, &req).unwrap()).unwrap();
        let resp = bus.recv(0).unwrap().unwrap();
        assert_eq!((resp.id, resp.data[0]), (0x583, 0x60), "{resp}");
    }
}

#[test]
fn save_and_resume_keep_offsets_calibration_and_pose_and_boot_like_a_reset() {
    let cfg = RobotConfig::prob2_default();
    let (mut bus, mut m) = enabled(&cfg, false);
    apply(
        &mut bus,
        SimCommand {
            power_cycle: true,
            ..SimCommand::default()
        },
    );
    m.run_until_enabled(&mut bus, 100);
    // Store a calibration in drive 3 (node 3) by SDO (between SYNCs: only the answers queue).
    while bus.recv(0).unwrap().is_some() {}
    store_calibration_12345_in_node_3(&mut bus);
    let path = std::env::temp_dir().join(format!("mcm-sim-test-{}.state", std::process::id()));
    assert!(SimBus::resume(&cfg, &path).unwrap().is_none(), "no file");
    bus.save(&path).unwrap();
    let mut resumed = SimBus::resume(&cfg, &path).unwrap().unwrap();
    std::fs::remove_file(&path).unwrap();
    for i in 0..NUM_AXES {
        let (a, b) = (bus.drive(i).unwrap(), resumed.drive(i).unwrap());
        assert_eq!(a.retained(), b.retained(), "drive {i}");
        assert_eq!(a.retained().power_cycles, 1);
    }
    let r = resumed.drive(2).unwrap().retained();
    assert_eq!((r.calibration_offset, r.calibration_valid), (12345, 1));
    let t = resumed.truth();
    assert_eq!(t.position, bus.truth().position, "exact joint angles");
    assert_eq!(t.velocity, [0.0; NUM_AXES], "at rest");
    let mut frames = Vec::new();
    while let Some(f) = resumed.recv(0).unwrap() {
        frames.push(f.to_string());
    }
    assert_eq!(
        frames,
        ["701#00", "702#00", "703#00", "704#00", "705#00", "706#00"]
    );

    std::fs::write(&path, "mcm-sim-state 1\narm 0 0 0\n").unwrap();
    let err = SimBus::resume(&cfg, &path).unwrap_err();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidData, "{err}");
}

/// The frames from node `node` among `frames` (its TPDOs, EMCY, SDO answers, heartbeats).
fn from_node(frames: &[Frame], node: u8) -> Vec<Frame> {
    frames
        .iter()
        .filter(|f| f.id != 0x080 && f.id & 0x7F == u16::from(node))
        .copied()
        .collect()
}

#[test]
fn a_drive_rebooting_alone_is_dead_while_off_then_boots_as_at_power_up() {
    use crate::cia402::State;
    use crate::nmt::NmtState;
    use crate::od;
    let cfg = cfg_at([0.0, 30.0, -60.0, 0.0, 45.0, 0.0]);
    let (mut bus, mut m) = enabled(&cfg, true);
    // A stored calibration in drive 3 (node 3), which its reboot must clear.
    while let Some(f) = bus.recv(0).unwrap() {
        m.received.push(f);
    }
    store_calibration_12345_in_node_3(&mut bus);
    let node = cfg.axes[2].node_id;
    let d = bus.drive(2).unwrap();
    let offset = d.encoder_offset_counts();
    assert_ne!(d.od().raw(od::PRODUCER_HEARTBEAT), 0, "configured");
    assert_ne!(d.od().raw(od::TPDO_MAP[0]), 0, "configured");
    let tpdos: Vec<u64> = m.nodes.iter().map(|n| n.tpdos).collect();

    bus.power_off_drive(2);
    let d = bus.drive(2).unwrap();
    assert_eq!((d.state(), d.current_a()), (State::NotReadyToSwitchOn, 0.0));
    let heard = m.received.len();
    let read_1017 = [0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0];
    bus.send(&Frame::new(0x603, &read_1017).unwrap()).unwrap();
    let truths = run(&mut bus, &mut m, 40); // 200 ms, four heartbeat periods
    assert_eq!(
        from_node(&m.received[heard..], node),
        [],
        "a drive without power answers nothing and sends nothing, heartbeats included"
    );
    let d = bus.drive(2).unwrap();
    assert!(!d.powered());
    assert_eq!(
        (d.state(), d.current_a()),
        (State::NotReadyToSwitchOn, 0.0),
        "no SYNC moves a drive without power"
    );
    for (i, n) in m.nodes.iter().enumerate() {
        let got = n.tpdos - tpdos[i];
        // The TPDOs of the SYNC before went with the SDO answers, the 40th's wait to be read.
        assert_eq!(got, if i == 2 { 0 } else { 39 }, "node {}", n.node);
        assert!(i == 2 || n.is_enabled(), "node {} enabled", n.node);
    }
    assert!(
        (truths[39].position[2] - truths[0].position[2]).abs() > 0.1 * DEG,
        "axis 3 unpowered sags under gravity: {} -> {} deg",
        truths[0].position[2] / DEG,
        truths[39].position[2] / DEG
    );

    bus.power_on_drive(2);
    let heard = m.received.len();
    let q = bus.truth().position[2]; // where the next SYNC samples it
    run(&mut bus, &mut m, 1);
    let boot: Vec<String> = from_node(&m.received[heard..], node)
        .iter()
        .map(Frame::to_string)
        .collect();
    assert_eq!(
        boot,
        ["703#00"],
        "its boot-up frame, then nothing (0x1017 = 0)"
    );
    for n in &m.nodes {
        assert_eq!(
            n.boot_ups,
            if n.node == node { 2 } else { 1 },
            "node {}",
            n.node
        );
    }
    let d = bus.drive(2).unwrap();
    assert_eq!(d.nmt_state(), NmtState::PreOperational);
    assert_eq!(d.state(), State::SwitchOnDisabled, "after its first SYNC");
    assert_eq!(d.od().raw(od::PRODUCER_HEARTBEAT), 0, "heartbeat off");
    assert_eq!(d.od().raw(od::TPDO_MAP[0]), 0, "mapping back to power-up");
    assert_eq!(d.od().raw(od::RPDO_MAP[0]), 0, "mapping back to power-up");
    let r = d.retained();
    assert_eq!(
        (r.calibration_offset, r.calibration_valid, r.power_cycles),
        (0, 0, 1),
        "the stored calibration is gone"
    );
    assert_ne!(d.encoder_offset_counts(), offset, "a new encoder offset");
    let measured = f64::from(bus.drive(2).unwrap().od().i32(od::POSITION_ACTUAL));
    let expected = q * cfg.axes[2].counts_per_rad() + d.encoder_offset_counts() as f64;
    assert!(
        (measured - expected).abs() < 50.0,
        "the encoder reads the joint where the physics has it"
    );
    m.run_until_enabled(&mut bus, 100);
    assert!(
        m.nodes.iter().all(|n| n.aborts.is_empty()),
        "configured again"
    );
}

/// [`SimBus`] with its SYNCs lost on the wire: each SYNC the master sends is a period without it.
struct SyncLost<'a>(&'a mut SimBus);

impl Bus for SyncLost<'_> {
    fn send(&mut self, frame: &Frame) -> Result<(), mcm_bus::BusError> {
        if frame.id == super::SYNC_ID {
            self.0.period_without_sync();
            return Ok(());
        }
        self.0.send(frame)
    }
    fn recv(&mut self, deadline_ns: u64) -> Result<Option<Frame>, mcm_bus::BusError> {
        self.0.recv(deadline_ns)
    }
}

#[test]
fn without_sync_time_and_physics_go_on_the_drives_hold_their_setpoint_and_send_no_tpdo() {
    let cfg = cfg_at([0.0, 30.0, -60.0, 0.0, 45.0, 0.0]);
    let (mut bus, mut m) = enabled(&cfg, true);
    run(&mut bus, &mut m, 40);
    // A target 2 deg away on axis 1, sent once: it reaches the drive only with a SYNC.
    let step = (2.0 * DEG * cfg.axes[0].counts_per_rad()) as i32;
    m.nodes[0].target += step;
    let held = target_angle(&cfg, &bus, &m, 0) - 2.0 * DEG;
    let t0 = bus.now_ns();
    let tpdos: Vec<u64> = m.nodes.iter().map(|n| n.tpdos).collect();
    let heard = m.received.len();
    // Fewer periods than a drive waits before it faults for want of SYNC (the test below).
    let periods = SYNC_LOSS_PERIODS - 5;
    let truths: Vec<SimTruth> = (0..periods)
        .map(|_| {
            m.run_cycle(&mut SyncLost(&mut bus));
            bus.truth()
        })
        .collect();
    assert_eq!(
        bus.now_ns() - t0,
        u64::from(periods) * cfg.cycle_period_ns(),
        "time goes on"
    );
    for (i, n) in m.nodes.iter().enumerate() {
        assert_eq!(
            n.tpdos - tpdos[i],
            1,
            "node {}: only the last SYNC's TPDO",
            n.node
        );
        let heartbeats = from_node(&m.received[heard..], n.node)
            .iter()
            .filter(|f| f.id == 0x700 + u16::from(n.node))
            .count();
        assert!(heartbeats >= 5, "node {}: {heartbeats} heartbeats", n.node);
        assert!(n.is_enabled(), "node {}", n.node);
    }
    // The new target never arrived: axis 1 holds the last one it had.
    let err = max_error_deg(&truths, &[held; NUM_AXES])[0];
    assert!(err < 0.05, "axis 1 off its last setpoint by {err} deg");
    // A push moves the arm: the physics runs although no SYNC comes.
    let mut tau = [0.0; NUM_AXES];
    tau[0] = 40.0;
    apply(
        &mut bus,
        SimCommand {
            external_torques_nm: Some(tau),
            ..SimCommand::default()
        },
    );
    let before = bus.truth().position[0];
    for _ in 0..4 {
        m.run_cycle(&mut SyncLost(&mut bus));
    }
    assert!(
        bus.truth().position[0] > before + 1e-4 * DEG,
        "the push moved axis 1: {} -> {} deg",
        before / DEG,
        bus.truth().position[0] / DEG
    );
    // SYNC back: the latched target applies and the TPDOs come again.
    let tpdos = m.nodes[0].tpdos;
    run(&mut bus, &mut m, 100);
    assert_eq!(m.nodes[0].tpdos - tpdos, 99, "the 100th waits to be read");
    let at = bus.truth().position[0];
    let reached = target_angle(&cfg, &bus, &m, 0);
    assert!(
        (at - reached).abs() < 0.1 * DEG,
        "{} vs {} deg",
        at / DEG,
        reached / DEG
    );
}

/// Without SYNC an enabled drive applies no setpoint, so the master can neither move nor disable
/// it: after [`SYNC_LOSS_PERIODS`] periods it faults by itself (EMCY 0x8250, RPDO timeout) and
/// its motor goes off onto its brake, not one period earlier.
#[test]
fn an_enabled_drive_without_sync_faults_onto_its_brake() {
    let cfg = cfg_at([0.0, 30.0, -60.0, 0.0, 45.0, 0.0]);
    let (mut bus, mut m) = enabled(&cfg, true);
    run(&mut bus, &mut m, 40);
    let heard = m.received.len();
    for _ in 0..SYNC_LOSS_PERIODS - 1 {
        m.run_cycle(&mut SyncLost(&mut bus));
    }
    assert!(
        (0..NUM_AXES).all(|i| bus.drive(i).unwrap().state() == State::OperationEnabled),
        "still enabled"
    );
    for _ in 0..3 {
        m.run_cycle(&mut SyncLost(&mut bus));
    }
    for (i, n) in m.nodes.iter().enumerate() {
        let d = bus.drive(i).unwrap();
        assert_eq!(d.state(), State::Fault, "node {} faulted", n.node);
        assert_eq!(d.counters().sync_losses, 1, "node {}", n.node);
        assert_eq!(
            d.brake_engaged(),
            cfg.axes[i].brake,
            "node {}: its brake",
            n.node
        );
        let emcy = from_node(&m.received[heard..], n.node)
            .into_iter()
            .find(|f| f.id == EMCY_BASE + u16::from(n.node))
            .unwrap_or_else(|| panic!("node {}: no EMCY", n.node));
        assert_eq!(
            u16::from_le_bytes([emcy.data[0], emcy.data[1]]),
            EMCY_SYNC_LOSS.0,
            "node {}",
            n.node
        );
    }
}

/// A CiA 301 event timer runs on the drive's clock: TPDO2 with its event timer set (as the
/// MCM's boot sets it, 100 ms) is repeated while no SYNC, nor any other frame, comes.
#[test]
fn an_event_timer_repeats_tpdo2_without_sync() {
    let cfg = cfg_at([0.0; NUM_AXES]);
    let (mut bus, mut m) = enabled(&cfg, true);
    for n in 1..=6u8 {
        // SDO expedited download of 2 bytes: 0x1801:5 = 100 ms.
        let sdo = Frame {
            id: 0x600 + u16::from(n),
            len: 8,
            data: [0x2B, 0x01, 0x18, 0x05, 100, 0, 0, 0],
        };
        bus.send(&sdo).unwrap();
    }
    // The answers (0x580 + node) are not the test master's to read.
    let mut answers = 0;
    while let Some(f) = bus.recv(0).unwrap() {
        answers += usize::from(f.id & 0xFF80 == 0x580 && f.data[0] == 0x60);
    }
    assert_eq!(answers, 6, "every drive took the event timer");
    run(&mut bus, &mut m, 4);
    // The master silent (nothing reaches the drives, SYNC or other): 0.5 s on their clocks.
    let mut heard = Vec::new();
    for _ in 0..100 {
        bus.period_without_sync();
        while let Some(f) = bus.recv(0).unwrap() {
            heard.push(f);
        }
    }
    for n in 1..=6u8 {
        let tpdo2 = heard
            .iter()
            .filter(|f| f.id == 0x280 + u16::from(n))
            .count();
        assert!(tpdo2 >= 4, "node {n}: {tpdo2} TPDO2 in 0.5 s without SYNC");
    }
}

#[test]
fn true_tool_changes_the_load_of_the_simulated_arm() {
    let cfg = RobotConfig::prob2_default();
    let mut bus = SimBus::new(&cfg);
    let configured = cfg.arm.tool.active();
    assert_eq!(bus.arm().model().tool(), &configured);
    let load = SimCommand::true_tool(2.0, [0.0, 0.0, 0.06]).unwrap();
    apply(
        &mut bus,
        SimCommand {
            true_tool: Some(load),
            ..SimCommand::default()
        },
    );
    let tool = bus.arm().model().tool();
    assert_eq!((tool.mass, tool.center_of_mass), (2.0, [0.0, 0.0, 0.06]));
    assert!((bus.arm().model().total_mass() - (16.7 - 3.8 + 2.0)).abs() < 1e-9);
}
