use super::*;

/// The router's own refusals carry their codes (a ZeroMQ peer reads them as a JSON client
/// does).
#[test]
fn a_full_queue_and_a_full_peer_table_are_told_with_their_codes() {
    let v = queue_full();
    assert_eq!(v["error_code"], "too_many_requests", "{v}");
    assert!(
        v["error_message"]
            .as_str()
            .unwrap()
            .contains("nothing was done"),
        "{v}"
    );
    let v = peers_full(3);
    assert_eq!(v["error_code"], "too_many_connections", "{v}");
    assert!(
        v["error_message"].as_str().unwrap().contains("at most 3"),
        "{v}"
    );
}
