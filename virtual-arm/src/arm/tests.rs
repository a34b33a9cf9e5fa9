use super::*;
use crate::memory_wire::{End, pair};

const P: u64 = 5_000_000;

fn arm() -> (VirtualArm<End>, End) {
    let cfg = RobotConfig::prob2_default();
    assert_eq!(cfg.cycle_period_ns(), P);
    let (arm_end, master_end) = pair();
    (VirtualArm::new(&cfg, arm_end, 2, 0), master_end)
}

fn drain(end: &mut End) -> Vec<Frame> {
    std::iter::from_fn(|| end.recv(0).unwrap()).collect()
}

#[test]
fn the_drives_boot_up_frames_reach_the_wire_at_the_first_poll() {
    let (mut arm, mut master) = arm();
    let mut events = Vec::new();
    arm.poll(0, &mut |e| events.push(e));
    let ids: Vec<u16> = drain(&mut master).iter().map(|f| f.id).collect();
    assert_eq!(ids, [0x701, 0x702, 0x703, 0x704, 0x705, 0x706]);
    assert!(events.is_empty(), "{events:?}");
}

#[test]
fn a_sync_runs_one_period_and_an_sdo_is_answered_at_once() {
    let (mut arm, mut master) = arm();
    arm.poll(0, &mut |_| {});
    drain(&mut master);
    // SDO upload of 0x1000 from node 1.
    master
        .send(&Frame::new(0x601, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]).unwrap())
        .unwrap();
    master.send(&Frame::new(SYNC_ID, &[]).unwrap()).unwrap();
    let mut events = Vec::new();
    arm.poll(P, &mut |e| events.push(e));
    assert_eq!(events, [Event::FirstSync]);
    let out = drain(&mut master);
    assert_eq!(out.first().map(|f| f.id), Some(0x581), "{out:?}");
    assert_eq!(arm.sim().now_ns(), P);
    let c = arm.counters();
    assert_eq!((c.frames_in, c.syncs, c.periods_without_sync), (2, 1, 0));
    assert_eq!(
        c.frames_out,
        6 + out.len() as u64,
        "the boot-ups, then the answers"
    );
}

#[test]
fn without_a_master_the_arm_time_follows_the_clock_and_heartbeats_go_on() {
    let (mut arm, mut master) = arm();
    for ms in 0..=2000u64 {
        arm.poll(ms * 1_000_000, &mut |_| {});
    }
    // 400 periods due in 2 s, 2 within the grace.
    assert_eq!(arm.sim().now_ns(), 398 * P);
    assert_eq!(arm.counters().periods_without_sync, 398);
    let heartbeats = drain(&mut master)
        .iter()
        .filter(|f| (0x701..=0x706).contains(&f.id))
        .count();
    // The boot-ups, then the drives' own heartbeats if the dictionary produces them: at least
    // the boot-ups. (0x1017 is 0 at power-up: no heartbeat until the master configures it.)
    assert!(heartbeats >= 6, "{heartbeats}");
}

#[test]
fn a_silent_master_is_an_event_and_so_is_its_return() {
    let (mut arm, mut master) = arm();
    let mut events = Vec::new();
    let sync = Frame::new(SYNC_ID, &[]).unwrap();
    for k in 1..=10u64 {
        master.send(&sync).unwrap();
        arm.poll(k * P, &mut |e| events.push(e));
    }
    arm.poll(30 * P, &mut |e| events.push(e));
    master.send(&sync).unwrap();
    arm.poll(31 * P, &mut |e| events.push(e));
    assert_eq!(
        events,
        [
            Event::FirstSync,
            Event::SyncLost { periods: 18 },
            Event::SyncBack { periods: 18 }
        ]
    );
    assert_eq!(arm.sim().now_ns(), 29 * P);
}

#[test]
fn the_emergency_switch_is_injected_and_shows_in_the_truth() {
    let (mut arm, _master) = arm();
    let cmd = SimCommand {
        emergency_stop: Some(true),
        ..SimCommand::default()
    };
    let truth = arm.apply(&cmd, &mut |_| {}).unwrap();
    assert!(truth.emergency_stop);
    assert!(arm.truth().emergency_stop);
    assert_eq!(arm.counters().faults, 1);
    let bad = SimCommand {
        external_torques_nm: Some([f64::NAN; 6]),
        ..SimCommand::default()
    };
    assert!(arm.apply(&bad, &mut |_| {}).is_err());
    assert_eq!(arm.counters().faults, 1);
}
