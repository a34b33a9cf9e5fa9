use super::*;
use crate::command::Axis;
use crate::config::RobotConfig;
use crate::reply::{Done, Reason};

#[test]
fn refusals_failures_and_arguments_are_worded_with_their_command() {
    let busy = Reason::Busy { remaining_s: 0.5 };
    assert_eq!(
        Outcome::Refused(busy)
            .words(CommandKind::MoveAll)
            .to_string(),
        format!("move_all refused: {busy}")
    );
    assert_eq!(
        Outcome::Failed(busy)
            .words(CommandKind::Calibrate)
            .to_string(),
        format!("calibrate failed: {busy}")
    );
    assert_eq!(
        Outcome::Done(Done::Ack)
            .words(CommandKind::Hold)
            .to_string(),
        "hold done"
    );
    // A target out of reach reads as the gateway's refusal of the argument.
    let (min_deg, max_deg) = crate::ranges::reachable_deg(&RobotConfig::prob2_default(), 1);
    let far = Reason::Unreachable {
        axis: Axis::new(2).unwrap(),
        target_deg: 400.0,
        min_deg,
        max_deg,
    };
    let words = Outcome::Refused(far)
        .words(CommandKind::MoveAxis)
        .to_string();
    assert!(
        words.starts_with("move_axis: argument \"target_position\" = 400 is not allowed"),
        "{words}"
    );
    // Not an argument of `hold`: the reason's own words.
    assert_eq!(
        Outcome::Refused(far).words(CommandKind::Hold).to_string(),
        format!("hold refused: {far}")
    );
}

#[test]
fn a_safety_error_says_a_check_tripped() {
    let e = SafetyError {
        seq: 1,
        cycle: 2,
        unix_ns: 3,
        reason: Reason::EmergencyStop,
    };
    assert_eq!(
        e.to_string(),
        format!("safety check tripped: {}", Reason::EmergencyStop)
    );
}
