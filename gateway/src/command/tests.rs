use super::*;
use crate::command::access::{Access, Channel, Client, run_command};
use crate::core_link::bridge::NoReply;
use crate::core_link::lifecycle::Notice;
use mcm_shared::command::DecodeError;
use mcm_shared::config::Cidr;
use mcm_shared::protocol::Command;

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

// The gateway's own refusals carry their `error_code`, one level below the end-to-end test
// `tests/end_to_end/error_codes.rs` (which names, for each code it cannot provoke from outside,
// the test that checks it): the access rules, a core that does not run, a request whose answer
// never came or cannot be read, the notices about the core's life.

fn code(answer: &Option<Answer>) -> Option<ErrorCode> {
    match answer {
        Some(Answer::Generic(g)) if !g.is_ok() => g.code(),
        other => panic!("not an ERROR: {other:?}"),
    }
}

fn parse_in(ctx: &Context, json: &str) -> Command {
    Command::from_json(json, &ctx.cfg).expect("a valid command")
}

const MOVE: &str = r#"{"command":"move_axis","arguments":{"axis_index":1,"target_position":10}}"#;

/// Motion from outside the allowed networks, before the secret, with a wrong secret, `sim`
/// from afar; and a command the core does not answer because it does not run.
#[tokio::test]
async fn the_access_rules_and_an_absent_core_refuse_with_their_codes() {
    let (mut ctx, thread, _) =
        crate::test_support::offline_context("codes", RobotConfig::prob2_default());
    let only_lan = vec![Cidr::parse("192.168.0.0/16").expect("a network")];
    let secret = crate::command::access::sha256::digest(b"right");
    ctx.access = Arc::new(Access::new(Some(only_lan), Some(secret), false));
    let far = Client::new(
        &ctx.clients,
        &ctx.bridge,
        Channel::Json,
        "10.0.0.9:4000".parse().unwrap(),
    );
    let near = Client::new(
        &ctx.clients,
        &ctx.bridge,
        Channel::Json,
        "192.168.1.2:4000".parse().unwrap(),
    );
    let run = |client: &Client, json: &str| {
        let (ctx, client, cmd) = (ctx.clone(), client.clone(), parse_in(&ctx, json));
        async move { run_command(&ctx, &client, &cmd).await.result }
    };
    let cases = [
        (&far, MOVE, ErrorCode::NetworkRefused),
        (&near, MOVE, ErrorCode::NotAuthenticated),
        (
            &near,
            r#"{"command":"authenticate","arguments":{"secret":"wrong"}}"#,
            ErrorCode::WrongSecret,
        ),
        (
            &far,
            r#"{"command":"sim","arguments":{"emergency_stop":false}}"#,
            ErrorCode::RemoteSimRefused,
        ),
        (&far, r#"{"command":"status"}"#, ErrorCode::CoreUnavailable),
        (&far, r#"{"command":"hold"}"#, ErrorCode::CoreUnavailable),
    ];
    for (client, json, expected) in cases {
        assert_eq!(code(&run(client, json).await), Some(expected), "{json}");
    }
    // `authenticate` is the access rules' to answer: reaching `execute` is a fault.
    let auth = parse_in(
        &ctx,
        r#"{"command":"authenticate","arguments":{"secret":"x"}}"#,
    );
    let out = execute(&ctx, near.id, &auth).await;
    assert_eq!(code(&out.result), Some(ErrorCode::InternalError));
    thread.stop();
}

/// A request the bridge could not complete: the code says whether it may have been executed.
#[test]
fn a_request_the_bridge_could_not_complete_has_its_code() {
    let cases = [
        (
            BridgeError::RtNotRunning {
                instance: "r1".into(),
            },
            ErrorCode::CoreUnavailable,
        ),
        (
            BridgeError::OutcomeUnknown(NoReply::Timeout { seconds: 5.0 }),
            ErrorCode::OutcomeUnknown,
        ),
        (
            BridgeError::OutcomeUnknown(NoReply::CoreRestarted),
            ErrorCode::OutcomeUnknown,
        ),
        (
            BridgeError::Undecodable(DecodeError::UnknownKind(99)),
            ErrorCode::VersionMismatch,
        ),
        (BridgeError::NoRequest, ErrorCode::InternalError),
        (BridgeError::ShuttingDown, ErrorCode::ShuttingDown),
    ];
    for (e, expected) in cases {
        assert_eq!(code(&Some(bridge_error("hold", &e))), Some(expected), "{e}");
    }
}

/// The notices about the MCM's life, as every channel sends them.
#[test]
fn the_notices_have_their_codes() {
    let cases = [
        (Notice::RtStopping, "core_stopping"),
        (Notice::RtStopped, "core_stopped"),
        (Notice::RtVanished, "core_vanished"),
        (Notice::GatewayStopping, "gateway_stopping"),
    ];
    for (n, expected) in cases {
        let v = n.result();
        assert_eq!(v["error_code"], expected, "{v}");
        assert_eq!(v["error_message"], n.text(), "{v}");
    }
}

/// The `outcome` and `command` of an ERROR `answer`.
fn ended(answer: &Option<Answer>) -> (Option<ErrorOutcome>, Option<&str>) {
    match answer {
        Some(Answer::Generic(g)) if !g.is_ok() => (g.outcome(), g.command.as_deref()),
        other => panic!("not an ERROR: {other:?}"),
    }
}

/// Every ERROR that answers a command says how it ended, whatever its words: the core's
/// refusal and failure, the gateway's own refusal, a request whose answer never came or
/// cannot be read, a core that does not run; and names the command it answers.
#[tokio::test]
async fn errors_answering_a_command_say_how_it_ended_and_name_it() {
    use mcm_shared::command::Axis;
    use mcm_shared::reply::{CalibrationFailure, Reason};
    let (mut ctx, thread, _) =
        crate::test_support::offline_context("ended", RobotConfig::prob2_default());
    let core = |kind, outcome| {
        let g = crate::command::access::reply_error(&ctx, kind, &outcome);
        Some(Answer::Generic(g))
    };
    let busy = reply::Outcome::Refused(Reason::Busy { remaining_s: 1.0 });
    let not_owner = reply::Outcome::Refused(Reason::NotOwner { owner: 7 });
    let no_stop = reply::Outcome::Failed(Reason::CalibrationFailed {
        axis: Axis::new(3).unwrap(),
        cause: CalibrationFailure::NoStop {
            searched_deg: 310.0,
        },
    });
    let cases = [
        (core(CommandKind::MoveAxis, busy), ErrorOutcome::Refused),
        (
            core(CommandKind::SetTorques, not_owner),
            ErrorOutcome::Refused,
        ),
        (core(CommandKind::Calibrate, no_stop), ErrorOutcome::Failed),
        (
            Some(bridge_error(
                "hold",
                &BridgeError::OutcomeUnknown(NoReply::Timeout { seconds: 5.0 }),
            )),
            ErrorOutcome::Unknown,
        ),
        (
            Some(bridge_error(
                "hold",
                &BridgeError::Undecodable(DecodeError::UnknownKind(99)),
            )),
            ErrorOutcome::Unknown,
        ),
        (
            Some(bridge_error(
                "hold",
                &BridgeError::RtNotRunning {
                    instance: "r1".into(),
                },
            )),
            ErrorOutcome::Failed,
        ),
    ];
    for (answer, outcome) in cases {
        assert_eq!(ended(&answer).0, Some(outcome), "{answer:?}");
    }
    let state = StateSample {
        mode: 99,
        ..StateSample::default()
    };
    let hold = Command::Hold(mcm_shared::protocol::Hold);
    let unreadable = success(&ctx, &hold, &Done::Ack, &state);
    assert_eq!(ended(&unreadable).0, Some(ErrorOutcome::Unknown));

    // Through the access rules, as every channel runs a command: the command is named.
    let only_lan = vec![Cidr::parse("192.168.0.0/16").expect("a network")];
    ctx.access = Arc::new(Access::new(Some(only_lan), None, false));
    let far = Client::new(
        &ctx.clients,
        &ctx.bridge,
        Channel::Json,
        "10.0.0.9:4000".parse().unwrap(),
    );
    let torques = r#"{"command":"set_torques","arguments":{"torques":[0,0,0,0,0,0]}}"#;
    let out = run_command(&ctx, &far, &parse_in(&ctx, torques)).await;
    assert_eq!(
        ended(&out.result),
        (Some(ErrorOutcome::Invalid), Some("set_torques"))
    );
    let out = run_command(&ctx, &far, &parse_in(&ctx, r#"{"command":"status"}"#)).await;
    assert_eq!(code(&out.result), Some(ErrorCode::CoreUnavailable));
    assert_eq!(
        ended(&out.result),
        (Some(ErrorOutcome::Failed), Some("status"))
    );
    thread.stop();
}
