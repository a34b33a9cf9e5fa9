use super::*;
use std::ffi::CStr;

#[test]
fn a_panic_becomes_a_code_and_a_message() {
    let code = guard(
        "mcm_test",
        |_| {},
        || -> Result<(), Fail> { panic!("boom {}", 7) },
    );
    assert_eq!(code, MCM_ERR_PANIC);
    // SAFETY: mcm_last_error returns a valid NUL-terminated string of this thread.
    let m = unsafe { CStr::from_ptr(mcm_last_error()) }
        .to_str()
        .unwrap();
    assert!(
        m.contains("mcm_test: internal error") && m.contains("boom 7"),
        "{m}"
    );
}

#[test]
fn a_failure_is_recorded_with_its_reject_code_and_success_changes_nothing() {
    let mut handle = LastError::default();
    let code = guard(
        "mcm_test",
        |f| handle.set(f),
        || {
            Err(Fail {
                code: MCM_ERR_REFUSED,
                reject: 16,
                message: "move_axis refused: a\0motion".into(),
            })
        },
    );
    assert_eq!(code, MCM_ERR_REFUSED);
    assert_eq!(
        handle.message.to_str().unwrap(),
        "move_axis refused: a motion"
    );
    assert_eq!((handle.reject, mcm_last_reject()), (16, 16));
    assert_eq!(guard("mcm_test", |_| unreachable!(), || Ok(())), MCM_OK);
    assert_eq!(mcm_last_reject(), 16, "success leaves the last failure");
}

#[test]
fn each_shared_memory_error_keeps_its_code_and_the_mcms_reject_code() {
    use mcm_client::mcm_shared::mode::{CommandKind, Mode};
    use mcm_client::mcm_shared::reply::Reason;
    use std::time::Duration;
    let timeout = WaitError::Timeout {
        waited: Duration::from_millis(500),
        last_seq: 9,
    };
    assert_eq!(Fail::from(timeout.clone()).code, MCM_ERR_TIMEOUT);
    assert_eq!(
        Fail::from(RequestError::Wait(timeout.clone())).code,
        MCM_ERR_TIMEOUT
    );
    assert_eq!(
        Fail::from(WaitUntilError::Wait(timeout)).code,
        MCM_ERR_TIMEOUT
    );
    let not_reached = WaitUntilError::NotReached {
        what: "home".into(),
        waited: Duration::from_secs(1),
        last_seq: 3,
    };
    assert_eq!(Fail::from(not_reached).code, MCM_ERR_NOT_REACHED);
    let reason = Reason::WrongMode { mode: Mode::Hold };
    let f = Fail::from(RequestError::Refused {
        command: CommandKind::MoveAxis,
        reason,
    });
    assert_eq!(
        (f.code, f.reject, f.message.as_str()),
        (
            MCM_ERR_REFUSED,
            reason.code().to_wire(),
            format!("move_axis refused: {reason}").as_str()
        )
    );
    let unknown = RequestError::OutcomeUnknown {
        command: CommandKind::Hold,
        waited: Duration::from_secs(5),
        overwritten: false,
    };
    assert_eq!(Fail::from(unknown).code, MCM_ERR_OUTCOME_UNKNOWN);
    let name = OpenError::InstanceName(
        mcm_client::mcm_shared::service::ServiceNames::new("a/b").unwrap_err(),
    );
    assert_eq!(Fail::from(name).code, MCM_ERR_ARGUMENT);
}
