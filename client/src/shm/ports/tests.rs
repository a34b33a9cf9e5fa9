use super::*;
use mcm_shared::sample::ReplyBlock;

#[test]
fn the_expected_types_are_named_with_their_version_and_size() {
    assert_eq!(
        describe::<StateSample>(),
        "`mcm.StateSample.v7`, 1040 bytes, alignment 8"
    );
    assert_eq!(
        describe::<CommandSample>(),
        "`mcm.CommandSample.v1`, 536 bytes, alignment 8"
    );
    assert_eq!(
        describe::<ReplyBlock>(),
        "`mcm.ReplyBlock.v1`, 1792 bytes, alignment 8"
    );
}

#[test]
fn an_instance_without_services_is_not_running_for_either_peer() {
    let names = ServiceNames::new(&format!("ports-none-{}", std::process::id())).unwrap();
    for peer in [Peer::Client, Peer::Gateway] {
        let e = CorePorts::open(&names, peer)
            .err()
            .expect("nothing to open");
        assert!(e.is_not_running(), "{e}");
        let OpenError::NotRunning {
            service, source, ..
        } = &e
        else {
            panic!("{e:?}")
        };
        assert_eq!(service, &names.state());
        assert!(source.does_not_exist());
    }
}

#[test]
fn a_mismatch_names_the_peer_that_must_be_rebuilt() {
    let e = OpenError::Incompatible {
        service: "mcm/x/state".into(),
        peer: Peer::Gateway,
        mismatch: LayoutMismatch::StateKey(
            iceoryx2::service::builder::blackboard::BlackboardOpenError::IncompatibleKeys,
        ),
        expected: describe::<StateSample>(),
    };
    assert_eq!(
        e.to_string(),
        "service `mcm/x/state` of the running MCM does not match this gateway: its key type is \
         not u32; build the gateway from the same MCM version as the running core (iceoryx2 \
         =0.10.0, `mcm.StateSample.v7`, 1040 bytes, alignment 8)"
    );
    assert!(
        std::error::Error::source(&e).is_some(),
        "the mismatch is kept"
    );
}
