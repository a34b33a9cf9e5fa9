use super::*;

#[test]
fn nmt_frames_match_the_reference() {
    assert_eq!(nmt_frame(NmtCommand::Start, 0).to_string(), "000#0100");
    assert_eq!(nmt_frame(NmtCommand::Start, 5).to_string(), "000#0105");
    assert_eq!(nmt_frame(NmtCommand::Stop, 5).to_string(), "000#0205");
    assert_eq!(
        nmt_frame(NmtCommand::EnterPreOperational, 5).to_string(),
        "000#8005"
    );
    assert_eq!(nmt_frame(NmtCommand::ResetNode, 5).to_string(), "000#8105");
    assert_eq!(
        nmt_frame(NmtCommand::ResetCommunication, 5).to_string(),
        "000#8205"
    );
}

#[test]
fn sync_is_an_empty_frame_on_080() {
    assert_eq!(sync_frame().to_string(), "080#");
}

#[test]
fn heartbeat_and_boot_up_frames() {
    assert_eq!(
        heartbeat_frame(127, NmtState::Operational).to_string(),
        "77F#05"
    );
    assert_eq!(heartbeat_frame(3, NmtState::BootUp).to_string(), "703#00");
    for (b, s) in [
        (0x00, NmtState::BootUp),
        (0x04, NmtState::Stopped),
        (0x05, NmtState::Operational),
        (0x7F, NmtState::PreOperational),
    ] {
        let f = Frame::new(0x705, &[b]).unwrap();
        assert_eq!(decode_heartbeat(&f), Some(s));
        assert_eq!(s.to_byte(), b);
    }
    assert_eq!(decode_heartbeat(&Frame::new(0x705, &[]).unwrap()), None);
    assert_eq!(
        decode_heartbeat(&Frame::new(0x705, &[0x33]).unwrap()),
        Some(NmtState::Unknown(0x33))
    );
}
