//! The bridge against real iceoryx2 services, each test under its own instance name.

use super::ports::{LayoutMismatch, OpenError, open_ports};
use iceoryx2::prelude::*;
use iceoryx2::service::{builder, port_factory};
use mcm_shared::sample::StateSample;
use mcm_shared::service::{STATE_KEY, ServiceNames};

fn names(test: &str) -> ServiceNames {
    ServiceNames::new(&format!("gwtest-{test}-{}", std::process::id())).unwrap()
}

fn node(names: &ServiceNames) -> Node<ipc::Service> {
    set_log_level_from_env_or(LogLevel::Fatal);
    NodeBuilder::new()
        .name(&names.node("fake-rt").as_str().try_into().unwrap())
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .unwrap()
}

/// The creator of the state blackboard of `names` (keys `u32`), its entries still to add.
fn state_creator(
    node: &Node<ipc::Service>,
    names: &ServiceNames,
) -> builder::blackboard::Creator<u32, ipc::Service> {
    node.service_builder(&names.state().as_str().try_into().unwrap())
        .blackboard_creator::<u32>()
}

/// The state blackboard of a core whose state sample is another type (here a `u64`, as a
/// `StateSample` of another version would be) under the same key.
fn state_of_another_layout(
    node: &Node<ipc::Service>,
    names: &ServiceNames,
) -> port_factory::blackboard::PortFactory<ipc::Service, u32> {
    state_creator(node, names)
        .add::<u64>(STATE_KEY, 0)
        .create()
        .unwrap()
}

/// What does not match in `e`; panics unless `e` is an incompatible layout.
fn layout_mismatch(e: &OpenError) -> &LayoutMismatch {
    match e {
        OpenError::IncompatibleLayout { source, .. } => source,
        e => panic!("{e:?}"),
    }
}

#[test]
fn no_services_means_not_running() {
    let e = open_ports(&names("none")).err().expect("nothing to open");
    assert!(e.is_not_running(), "{e}");
}

#[test]
fn a_state_entry_of_another_layout_is_an_incompatible_layout() {
    let names = names("state");
    let node = node(&names);
    let _state = state_of_another_layout(&node, &names);
    let e = open_ports(&names).err().expect("the layouts differ");
    assert!(
        matches!(layout_mismatch(&e), LayoutMismatch::StateEntry(_)),
        "{e:?}"
    );
    assert!(!e.is_not_running());
    let text = e.to_string();
    assert!(
        text.contains("built with a different sample layout than mcm-rt")
            && text.contains(&names.state())
            && text.ends_with("rebuild both from the same version"),
        "{text}"
    );
}

#[test]
fn a_command_service_of_another_payload_is_an_incompatible_layout() {
    let names = names("command");
    let node = node(&names);
    let mut state =
        state_creator(&node, &names).add::<StateSample>(STATE_KEY, StateSample::default());
    for key in 1..=mcm_shared::sample::REPLY_BLOCKS as u32 {
        state = state.add::<mcm_shared::sample::ReplyBlock>(key, Default::default());
    }
    let _state = state.create().unwrap();
    let _command = node
        .service_builder(&names.command().as_str().try_into().unwrap())
        .publish_subscribe::<[u64; 4]>()
        .create()
        .unwrap();
    let e = open_ports(&names).err().expect("the layouts differ");
    assert!(
        matches!(layout_mismatch(&e), LayoutMismatch::CommandPayload(_)),
        "{e:?}"
    );
    assert!(e.to_string().contains(&names.command()), "{e}");
}

#[tokio::test]
async fn requests_get_the_layout_error_not_not_running() {
    let names = names("bridge");
    let node = node(&names);
    let _state = state_of_another_layout(&node, &names);
    let (bridge, thread) = super::Bridge::start(&names, "/tmp");
    // The thread tries to open the services before it takes any request.
    let e = bridge
        .request(
            bridge.new_client_id(),
            vec![mcm_shared::command::Request::Status],
            std::time::Duration::from_secs(1),
        )
        .await
        .unwrap_err();
    thread.stop();
    let super::BridgeError::IncompatibleLayout { instance, error } = &e else {
        panic!("{e:?}");
    };
    assert_eq!(instance, names.instance());
    assert!(error.contains("different sample layout"), "{e}");
}
