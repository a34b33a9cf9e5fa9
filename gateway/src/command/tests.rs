use super::*;
use crate::core_link::bridge::NoReply;

/// A state this version cannot read (a core of another MCM version) answers `hold` with an
/// ERROR that names `hold`, not `status`.
#[test]
fn a_status_that_cannot_be_built_names_the_command_it_answers() {
    let (ctx, thread, _) =
        crate::test_support::offline_context("label", RobotConfig::prob2_default());
    let state = StateSample {
        mode: 99,
        ..StateSample::default()
    };
    let hold = Command::Hold(mcm_shared::protocol::Hold);
    let answer = success(&ctx, &hold, &Done::Ack, &state);
    thread.stop();
    let Some(Answer::Generic(g)) = &answer else {
        panic!("{answer:?}")
    };
    assert!(
        g.message().starts_with("hold: the real-time core reports"),
        "{}",
        g.message()
    );
}

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
