use super::*;
use core::mem::{align_of, offset_of, size_of};

#[test]
fn command_sample_layout_is_pinned() {
    assert_eq!(size_of::<CommandSample>(), 536);
    assert_eq!(align_of::<CommandSample>(), 8);
    assert_eq!(offset_of!(CommandSample, client_id), 0);
    assert_eq!(offset_of!(CommandSample, request_id), 8);
    assert_eq!(offset_of!(CommandSample, kind), 16);
    assert_eq!(offset_of!(CommandSample, flags), 20);
    assert_eq!(offset_of!(CommandSample, args), 24);
}

#[test]
fn reply_and_error_layouts_are_pinned() {
    assert_eq!(size_of::<Reply>(), 112);
    assert_eq!(offset_of!(Reply, seq), 0);
    assert_eq!(offset_of!(Reply, client_id), 8);
    assert_eq!(offset_of!(Reply, request_id), 16);
    assert_eq!(offset_of!(Reply, cycle), 24);
    assert_eq!(offset_of!(Reply, kind), 32);
    assert_eq!(offset_of!(Reply, status), 36);
    assert_eq!(offset_of!(Reply, code), 40);
    assert_eq!(offset_of!(Reply, axis), 44);
    assert_eq!(offset_of!(Reply, values), 48);
    assert_eq!(size_of::<ReplyBlock>(), 112 * REPLY_BLOCK);
    assert_eq!(size_of::<ErrorRecord>(), 64);
    assert_eq!(offset_of!(ErrorRecord, unix_ns), 16);
    assert_eq!(offset_of!(ErrorRecord, code), 24);
    assert_eq!(offset_of!(ErrorRecord, values), 32);
    assert_eq!(size_of::<LatencyFigures>(), 48);
    assert_eq!(size_of::<CycleTiming>(), 144);
    assert_eq!(offset_of!(CycleTiming, since_start), 16);
    assert_eq!(offset_of!(CycleTiming, recent), 64);
    assert_eq!(offset_of!(CycleTiming, recent_window_ns), 112);
    assert_eq!(offset_of!(CycleTiming, over_budget), 136);
}

#[test]
fn state_sample_layout_is_pinned() {
    assert_eq!(align_of::<StateSample>(), 8);
    let expected = [
        (offset_of!(StateSample, seq), 0),
        (offset_of!(StateSample, t_ns), 8),
        (offset_of!(StateSample, mode), 16),
        (offset_of!(StateSample, flags), 20),
        (offset_of!(StateSample, position), 24),
        (offset_of!(StateSample, velocity), 72),
        (offset_of!(StateSample, acceleration), 120),
        (offset_of!(StateSample, current), 168),
        (offset_of!(StateSample, measured_position), 216),
        (offset_of!(StateSample, commanded_position), 264),
        (offset_of!(StateSample, following_error), 312),
        (offset_of!(StateSample, i2t), 360),
        (offset_of!(StateSample, sim_true_position), 408),
        (offset_of!(StateSample, sim_true_velocity), 456),
        (offset_of!(StateSample, axis_flags), 504),
        (offset_of!(StateSample, pvt_queued), 528),
        (offset_of!(StateSample, pvt_capacity), 532),
        (offset_of!(StateSample, command_receive_errors), 536),
        (offset_of!(StateSample, timing), 544),
        (offset_of!(StateSample, last_error), 688),
        (offset_of!(StateSample, reply_head), 752),
        (offset_of!(StateSample, owner_client_id), 760),
        (offset_of!(StateSample, bus), 768),
        (offset_of!(StateSample, cartesian), 800),
        (offset_of!(StateSample, tool), 904),
    ];
    for (i, (got, want)) in expected.iter().enumerate() {
        assert_eq!(got, want, "field #{i} moved");
    }
    assert_eq!(size_of::<StateSample>(), 1040);
    assert_eq!(size_of::<ToolState>(), 136);
    assert_eq!(offset_of!(ToolState, tcp_position), 0);
    assert_eq!(offset_of!(ToolState, tcp_orientation), 24);
    assert_eq!(offset_of!(ToolState, mass), 56);
    assert_eq!(offset_of!(ToolState, center_of_mass), 64);
    assert_eq!(offset_of!(ToolState, inertia), 88);
    assert_eq!(size_of::<BusCounters>(), 32);
    assert_eq!(offset_of!(BusCounters, bad_frames), 0);
    assert_eq!(offset_of!(BusCounters, frames_dropped), 8);
    assert_eq!(offset_of!(BusCounters, events_dropped), 16);
    assert_eq!(offset_of!(BusCounters, bus_errors), 24);
    assert_eq!(size_of::<TcpState>(), 104);
    assert_eq!(align_of::<TcpState>(), 8);
    assert_eq!(offset_of!(TcpState, position), 0);
    assert_eq!(offset_of!(TcpState, orientation), 24);
    assert_eq!(offset_of!(TcpState, linear_velocity), 56);
    assert_eq!(offset_of!(TcpState, angular_velocity), 80);
}

#[test]
fn flight_recorder_file_names_instance_time_and_check() {
    let e = ErrorRecord {
        seq: 3,
        unix_ns: 1_700_000_000_123_456_789,
        code: crate::mode::RejectCode::FollowingError.to_wire(),
        ..ErrorRecord::default()
    };
    let p = flight_recorder_file("/var/log/mcm", "robot1", &e);
    assert_eq!(
        p.to_str().unwrap(),
        "/var/log/mcm/mcm-robot1-1700000000123-following_error.csv"
    );
}

#[test]
fn replies_fill_blocks_in_order_and_wrap_after_the_last_block() {
    assert_eq!(reply_location(1), (1, 0));
    assert_eq!(reply_location(16), (1, 15));
    assert_eq!(reply_location(17), (2, 0));
    let last = (REPLY_BLOCKS * REPLY_BLOCK) as u64;
    assert_eq!(reply_location(last), (REPLY_BLOCKS as u32, REPLY_BLOCK - 1));
    assert_eq!(reply_location(last + 1), (1, 0));
    // Never key 0 (the state), whatever the sequence number.
    for seq in [0, 1, u64::MAX, u64::MAX / 2, last * 7 + 3] {
        let (key, slot) = reply_location(seq);
        assert!((1..=REPLY_BLOCKS as u32).contains(&key), "{seq}: key {key}");
        assert!(slot < REPLY_BLOCK);
    }
}

#[test]
fn a_block_gives_a_reply_only_while_its_slot_holds_it() {
    let mut block = ReplyBlock::default();
    assert_eq!(block.reply(3), None, "not written yet");
    block.replies[2].seq = 3;
    block.replies[2].request_id = 9;
    assert_eq!(block.reply(3).map(|r| r.request_id), Some(9));
    // The reply of the same slot one round of the blackboard later is not there yet.
    let later = 3 + (REPLY_BLOCKS * REPLY_BLOCK) as u64;
    assert_eq!(block.reply(later), None);
}
