use super::*;
use mcm_shared::command::Request;

#[test]
fn a_client_sends_from_a_new_connection_after_its_client_gone() {
    let mut s = Sender::new(2);
    let a = s.send(Request::Status.encode());
    let gone = s.send(Request::ClientGone.encode());
    let b = s.send(Request::Status.encode());
    assert_eq!((a.client_id, a.request_id), (FIRST_CLIENT_ID + 2, 1));
    assert_eq!((gone.client_id, gone.request_id), (FIRST_CLIENT_ID + 2, 2));
    assert_eq!(
        (b.client_id, b.request_id),
        (FIRST_CLIENT_ID + 2 + SCRIPT_CLIENTS as u64, 1)
    );
}
