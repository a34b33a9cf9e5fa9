use super::*;
use mcm_bus::Frame;
use mcm_shared::config::RobotConfig;

// The world counts what the cycle's work allocates, which needs the counting allocator (one
// for the crate's test binary).
#[global_allocator]
static GLOBAL: mcm_shared::alloc_count::CountingAlloc = mcm_shared::alloc_count::CountingAlloc;

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

#[test]
fn a_lost_sync_is_a_period_the_drives_miss_not_a_stop_of_the_world() {
    let cfg = RobotConfig::prob2_default();
    let mut bus = FaultyBus::new(SimBus::new(&cfg), Rng::new(1));
    bus.faults.lose_tx = 1.0;
    let sync = Frame::new(SYNC_ID, &[]).expect("a valid frame");
    bus.send(&sync).expect("the simulated bus does not fail");
    assert_eq!(bus.counts.lost_tx, 1, "the SYNC was lost");
    assert_eq!(
        bus.sim().now_ns(),
        cfg.cycle_period_ns(),
        "its period passed"
    );
    let drive = bus.sim().drive(0).expect("six drives");
    assert_eq!(
        drive.time_ns(),
        cfg.cycle_period_ns(),
        "on the drives' clocks too"
    );
}

use crate::world::World;
use mcm_shared::NUM_AXES;
use mcm_shared::sample::AXIS_ONLINE;

/// Whether each axis is online (configured, heard) in the world's last published state.
fn online(world: &World) -> [bool; NUM_AXES] {
    world.state().axis_flags.map(|f| f & AXIS_ONLINE != 0)
}

/// Step `world` until every axis is online; the cycles it took (at most `max`).
fn until_all_online(world: &mut World, max: u64) -> u64 {
    for k in 0..max {
        if online(world).iter().all(|&o| o) {
            return k;
        }
        world.step();
    }
    panic!(
        "not every axis online within {max} cycles: {:?}",
        online(world)
    );
}

#[test]
fn a_stuck_sync_starves_the_master_of_tpdos_while_time_goes_on_and_the_drives_are_stopped() {
    let cfg = RobotConfig::prob2_default();
    let mut world = World::new(&cfg, Rng::new(1));
    until_all_online(&mut world, 400);
    let t0 = world.bus().sim().now_ns();
    world.bus().faults.sync_stuck = true;
    let cycles = 2 * u64::from(cfg.bus.max_missed_tpdos) + 2;
    for _ in 0..cycles {
        world.step();
    }
    assert_eq!(world.bus().counts.syncs_stuck, cycles);
    assert_eq!(
        world.bus().sim().now_ns() - t0,
        cycles * cfg.cycle_period_ns(),
        "the simulated robot's time goes on without SYNC"
    );
    assert_eq!(
        online(&world),
        [false; NUM_AXES],
        "no TPDO for {cycles} cycles: every drive lost (bus.max_missed_tpdos {})",
        cfg.bus.max_missed_tpdos
    );
    // OFF asks every drive to power off, and a lost one gets it by NMT stop (no SYNC to apply a
    // controlword): each drive was stopped, and is reset and configured again once the master
    // hears it STOPPED (a heartbeat every 50 ms, a boot of some 45 SDO transactions).
    for i in 0..NUM_AXES {
        let d = world.bus().sim().drive(i).expect("six drives");
        assert_eq!(d.counters().connection_aborts, 1, "drive of axis {}", i + 1);
    }
    world.bus().faults.sync_stuck = false;
    let back = until_all_online(&mut world, 200);
    assert!(back >= 40, "online again after a new boot, {back} cycles");
}

#[test]
fn a_rebooting_drive_is_heard_booting_and_the_master_configures_it_again() {
    let cfg = RobotConfig::prob2_default();
    let mut world = World::new(&cfg, Rng::new(1));
    until_all_online(&mut world, 400);
    // Off for two cycles: fewer than `bus.max_missed_tpdos`, so that the master learns of the
    // reboot from the boot-up frame, not from the TPDOs it misses.
    assert!(cfg.bus.max_missed_tpdos > 2);
    world.bus().faults.rebooting = Some(2);
    world.step();
    assert!(!world.bus().sim().drive(2).expect("six drives").powered());
    world.step();
    world.bus().faults.rebooting = None;
    world.step();
    let drive = world.bus().sim().drive(2).expect("six drives");
    assert!(drive.powered());
    assert_eq!(drive.retained().power_cycles, 1, "booted as at power-up");
    assert_eq!(world.bus().counts.reboots, 1);
    assert_eq!(
        online(&world),
        [true, true, false, true, true, true],
        "its boot-up heard at once (two TPDOs missed only): axis 3 being configured again, the others untouched"
    );
    // The configuration takes some 40 cycles; a drive the master missed would wait for
    // `bus.boot_timeout_ms` (2 s, 400 cycles) before it is reset.
    let back = until_all_online(&mut world, 100);
    assert!(back > 10, "configured again, {back} cycles");
    for i in 0..NUM_AXES {
        let d = world.bus().sim().drive(i).expect("six drives");
        assert_eq!(
            d.retained().power_cycles,
            u64::from(i == 2),
            "drive {}",
            i + 1
        );
    }
}

#[test]
fn delayed_frames_keep_the_order_of_their_cob_id_as_a_real_bus_and_socketcan_do() {
    let cfg = RobotConfig::prob2_default();
    let node = cfg.axes[0].node_id;
    let mut bus = FaultyBus::new(SimBus::new(&cfg), Rng::new(7));
    let sync = Frame::new(SYNC_ID, &[]).expect("a valid frame");
    let mut answers = Vec::new();
    let mut take = |bus: &mut FaultyBus| {
        while let Some(f) = bus.recv(0).expect("the simulated bus does not fail") {
            if f.id == 0x580 + u16::from(node) {
                // An abort (no such object) naming the index asked for: a tag per frame.
                answers.push(u16::from_le_bytes([f.data[1], f.data[2]]));
            }
        }
    };
    bus.faults.delay_rx = 0.3;
    const ASKED: u16 = 300;
    for k in 0..ASKED {
        let [i0, i1] = (0x2000 + k).to_le_bytes();
        let upload = Frame::new(0x600 + u16::from(node), &[0x40, i0, i1, 0, 0, 0, 0, 0])
            .expect("a valid frame");
        bus.send(&upload).expect("the simulated bus does not fail");
        bus.send(&sync).expect("the simulated bus does not fail");
        take(&mut bus);
    }
    // Faults off: what is still held back arrives, still in order behind its COB-ID.
    bus.faults = BusFaults::default();
    for _ in 0..=MAX_DELAY_SYNCS {
        bus.send(&sync).expect("the simulated bus does not fail");
        take(&mut bus);
    }
    assert!(bus.counts.delayed > 20, "{:?}", bus.counts);
    assert_eq!(bus.counts.lost_rx, 0, "none lost to a full queue");
    let asked: Vec<u16> = (0..ASKED).map(|k| 0x2000 + k).collect();
    assert_eq!(
        answers, asked,
        "the answers of node {node} in the order asked"
    );
}
