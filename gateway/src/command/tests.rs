use super::*;
use crate::core_link::bridge::NoReply;

#[test]
fn a_request_without_reply_has_an_unknown_outcome_never_a_failure() {
    let text = bridge_message(
        "move_axis",
        &BridgeError::OutcomeUnknown(NoReply::Timeout { seconds: 5.0 }),
    );
    assert_eq!(
        text,
        "move_axis: no reply from the real-time core within 5 s: the command may or may \
         not have been executed; check the state"
    );
    for why in [NoReply::CoreStopped, NoReply::CoreRestarted] {
        let text = bridge_message("pvt_points", &BridgeError::OutcomeUnknown(why));
        assert!(!text.contains("failed"), "{text}");
        assert!(text.contains("may or may not have been executed"), "{text}");
    }
    assert!(text_of_restart().contains("before it restarted"));
}

fn text_of_restart() -> String {
    bridge_message("hold", &BridgeError::OutcomeUnknown(NoReply::CoreRestarted))
}

#[test]
fn a_request_never_published_failed() {
    let e = BridgeError::RtNotRunning {
        instance: "r1".into(),
    };
    assert_eq!(
        bridge_message("hold", &e),
        "hold failed: the real-time core (mcm-rt, instance `r1`) is not running or not \
         answering"
    );
}
