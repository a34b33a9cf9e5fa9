use super::*;
use mcm_shared::mode::CommandKind;

fn send_error() -> SendError {
    SendError {
        command: CommandKind::PvtPoints,
        service: "mcm/t/command".into(),
        source: iceoryx2::port::SendError::ConnectionCorrupted,
    }
}

/// A send that fails in the middle of a batch leaves nothing of the batch waited for.
#[test]
fn a_send_failing_mid_batch_forgets_the_whole_batch() {
    let mut p = Pending::default();
    let mut next = 10;
    let mut ids = [0; 5];
    let e = p
        .send_each(&[(); 5], &mut ids, |_| {
            next += 1;
            if next == 13 {
                Err(send_error())
            } else {
                Ok(next)
            }
        })
        .unwrap_err();
    assert_eq!(e, send_error());
    assert!(p.is_empty(), "{p:?}");
    // The replies of the two sent are dropped as they come.
    for id in [11, 12] {
        let r = Reply {
            request_id: id,
            ..Reply::default()
        };
        assert!(!p.offer(&r));
    }
    assert!(p.is_empty(), "{p:?}");
}

#[test]
fn a_batch_sent_is_waited_for_until_each_reply_is_taken() {
    let mut p = Pending::default();
    let mut ids = [0; 2];
    let mut next = 0;
    p.send_each(&[(); 2], &mut ids, |_| {
        next += 1;
        Ok(next)
    })
    .unwrap();
    assert_eq!(ids, [1, 2]);
    assert!(p.offer(&Reply {
        request_id: 2,
        ..Reply::default()
    }));
    p.overwritten();
    assert_eq!(p.take(1), None, "not read yet");
    assert_eq!(p.take(2).map(|r| r.request_id), Some(2));
    assert!(p.forget(&ids), "replies were overwritten while it waited");
    assert!(p.is_empty());
    assert!(!p.forget(&[]), "forgotten with the batch");
}
