use super::*;
use crate::transport::json::connection::{Step, step};
use mcm_shared::config::RobotConfig;
use proptest::prelude::*;

fn reason(f: Frame) -> String {
    match f {
        Frame::Invalid { reason } => reason,
        other => panic!("not refused: {other:?}"),
    }
}

#[test]
fn one_command_per_message_without_a_line_end() {
    assert_eq!(
        frame(br#"{"command":"status"}"#),
        Frame::Object(r#"{"command":"status"}"#.into())
    );
    assert_eq!(
        frame(b" {\"command\":\"hold\"}\r\n"),
        Frame::Object(r#"{"command":"hold"}"#.into())
    );
    assert!(reason(frame(b"")).contains("empty message"));
    let cut = reason(frame(b"{\"command\":"));
    assert!(cut.contains("JSON"), "{cut}");
    assert!(
        reason(frame(br#"{"command":"hold"}{"command":"status"}"#))
            .contains("more than one command")
    );
    assert!(reason(frame(b"status")).contains("status"));
    let long = vec![b' '; MAX_COMMAND_BYTES + 1];
    assert!(reason(frame(&long)).contains("longer than the limit of 65536 bytes"));
}

#[test]
fn envelopes_of_req_and_dealer_peers_come_back_unchanged() {
    let req = Request::from_frames(vec![b"id".to_vec(), vec![], b"{}".to_vec()]).unwrap();
    assert_eq!(req.envelope, vec![b"id".to_vec(), vec![]]);
    assert_eq!(
        req.reply("R".into()),
        vec![b"id".to_vec(), vec![], b"R".to_vec()]
    );
    let dealer = Request::from_frames(vec![b"id".to_vec(), b"{}".to_vec()]).unwrap();
    assert_eq!(
        dealer.reply("R".into()),
        vec![b"id".to_vec(), b"R".to_vec()]
    );
    assert_eq!(Request::from_frames(vec![b"id".to_vec()]), None);
}

proptest! {
    /// Whatever the bytes, one message is one step: a command or an ERROR result, and the
    /// connection-closing step of the TCP port never comes up.
    #[test]
    fn any_bytes_give_exactly_one_command_or_one_error(
        body in proptest::collection::vec(any::<u8>(), 0..300),
        json_like in "[{}\\[\\]\":, a-z0-9\\\\\n]{0,120}",
    ) {
        let cfg = RobotConfig::prob2_default();
        for bytes in [body.as_slice(), json_like.as_bytes()] {
            match step(frame(bytes), &cfg) {
                Step::Run(_) => {}
                Step::Reply(v) => prop_assert_eq!(&v["error_status"], "ERROR"),
                Step::Close(v) => prop_assert!(false, "closing step: {}", v),
                // Answered with one ERROR result by `peer::answer`.
                Step::Foreign(_) => {}
            }
        }
    }
}
