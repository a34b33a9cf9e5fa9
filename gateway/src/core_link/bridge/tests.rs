//! The bridge against real iceoryx2 services, each test under its own instance name. How the
//! services are opened (and a mismatch described) is the client library's, tested there
//! (`mcm_client::shm::ports`); here, what the bridge makes of it.

use super::OpenError;
use iceoryx2::prelude::*;
use iceoryx2::service::port_factory;
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

/// The state blackboard of a core whose state sample is another type (here a `u64`, as a
/// `StateSample` of another version would be) under the same key.
fn state_of_another_layout(
    node: &Node<ipc::Service>,
    names: &ServiceNames,
) -> port_factory::blackboard::PortFactory<ipc::Service, u32> {
    node.service_builder(&names.state_service())
        .blackboard_creator::<u32>()
        .add::<u64>(STATE_KEY, 0)
        .create()
        .unwrap()
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
    assert!(matches!(error, OpenError::Incompatible { .. }), "{error:?}");
    assert!(e.to_string().contains("does not match this gateway"), "{e}");
}
