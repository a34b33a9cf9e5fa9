use super::*;

#[test]
fn classifies_results() {
    let e = Answer::error(mcm_shared::error_code::ErrorCode::Busy, "x");
    let ok = Answer::ok();
    let state = mcm_shared::sample::StateSample {
        t_ns: 1_500_000_000,
        ..Default::default()
    };
    let s = Answer::Status(Box::new(Status::from_state(&state, false).unwrap()));
    assert!(is_error(&e) && !is_error(&ok) && !is_error(&s));
    assert_eq!(status_of(&s).map(Status::time), Some(1.5));
    assert!(status_of(&ok).is_none());
}

#[test]
fn the_lines_are_the_contract_s_commands() {
    let cfg = mcm_shared::config::RobotConfig::prob2_default();
    for (text, cmd) in [
        (&*STATUS, Command::from(protocol::Status { detail: false })),
        (&*STATUS_DETAIL, protocol::Status { detail: true }.into()),
        (&*HOLD, protocol::Hold.into()),
        (&*INFO, protocol::Info.into()),
    ] {
        assert_eq!(Command::from_json(text, &cfg).unwrap(), cmd, "{text}");
    }
}
