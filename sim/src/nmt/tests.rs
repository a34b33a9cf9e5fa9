use super::*;

#[test]
fn decodes_all_commands_and_broadcast() {
    let cases = [
        (0x01, NmtCommand::Start),
        (0x02, NmtCommand::Stop),
        (0x80, NmtCommand::EnterPreOperational),
        (0x81, NmtCommand::ResetNode),
        (0x82, NmtCommand::ResetCommunication),
    ];
    for (cs, cmd) in cases {
        assert_eq!(
            NmtCommand::decode(&Frame::new(0, &[cs, 4]).unwrap(), 4),
            Some(cmd)
        );
        assert_eq!(
            NmtCommand::decode(&Frame::new(0, &[cs, 0]).unwrap(), 4),
            Some(cmd)
        );
        assert_eq!(
            NmtCommand::decode(&Frame::new(0, &[cs, 5]).unwrap(), 4),
            None
        );
    }
    assert_eq!(
        NmtCommand::decode(&Frame::new(0, &[0x03, 4]).unwrap(), 4),
        None
    );
    assert_eq!(
        NmtCommand::decode(&Frame::new(0, &[0x01]).unwrap(), 4),
        None
    );
    assert_eq!(
        NmtCommand::decode(&Frame::new(0x80, &[0x01, 4]).unwrap(), 4),
        None
    );
}

#[test]
fn frames_and_state_bytes() {
    assert_eq!(boot_up_frame(3).to_string(), "703#00");
    assert_eq!(
        heartbeat_frame(3, NmtState::PreOperational.heartbeat_byte()).to_string(),
        "703#7F"
    );
    assert_eq!(NmtState::Operational.heartbeat_byte(), 0x05);
    assert_eq!(NmtState::Stopped.heartbeat_byte(), 0x04);
}

#[test]
fn producer_keeps_its_period_grid() {
    let mut p = HeartbeatProducer::default();
    assert!(!p.due(1_000_000_000), "off by default");
    p.configure(50, 0);
    let fired: Vec<u64> = (1..=40u64)
        .map(|k| k * 5_000_000)
        .filter(|&t| p.due(t))
        .collect();
    assert_eq!(fired, [50_000_000, 100_000_000, 150_000_000, 200_000_000]);
    p.configure(0, 0);
    assert!(!p.due(u64::MAX));
}

#[test]
fn consumer_arms_on_first_heartbeat_and_fires_once() {
    let mut c = HeartbeatConsumer::default();
    c.configure((127 << 16) | 150);
    assert!(
        !c.expired(10_000_000_000),
        "not armed before the first heartbeat"
    );
    let hb = heartbeat_frame(127, 0x05);
    c.on_frame(&hb, 100_000_000);
    c.on_frame(&heartbeat_frame(126, 0x05), 200_000_000); // someone else's
    assert!(
        !c.expired(250_000_000),
        "exactly the timeout is not yet missing"
    );
    assert!(c.expired(255_000_000));
    assert!(!c.expired(300_000_000), "fires once");
    c.on_frame(&hb, 300_000_000);
    assert!(c.expired(455_000_000));
    c.configure(0);
    c.on_frame(&hb, 0);
    assert!(!c.expired(10_000_000_000), "disabled by time 0");
}
