//! The set-up errors of the real-time core's iceoryx2 edge, provoked for real: services of the
//! same name left with another payload type (an MCM of another version), and a second core of
//! the same instance; and the state event waking a listener. Each test uses its own instance
//! name.

mod common;

use common::{node, state_listener};
use iceoryx2::port::writer::EntryHandleMutError;
use iceoryx2::prelude::*;
use iceoryx2::service::builder::publish_subscribe::PublishSubscribeOpenError;
use mcm_rt_core::ipc::{Incompatibility, IpcSetupError, PortTaken, RtIpc};
use mcm_shared::service::{STATE_EVENT_ID, STATE_KEY, STATE_MAX_READERS, ServiceNames};
use std::time::Duration;

/// A state sample of an older MCM version: another type name, another layout.
#[derive(Debug, Clone, Copy, Default, ZeroCopySend)]
#[repr(C)]
#[type_name("mcm.StateSample.v2")]
struct OldStateSample {
    seq: u64,
    position: [f64; 6],
}

/// A command sample of an older MCM version.
#[derive(Debug, Clone, Copy, Default, ZeroCopySend)]
#[repr(C)]
#[type_name("mcm.CommandSample.v0")]
struct OldCommandSample {
    kind: u32,
    args: [f64; 4],
}

fn names(test: &str) -> ServiceNames {
    ServiceNames::new(&format!("{test}-{}", std::process::id())).unwrap()
}

/// Set up a core of `names` while a service of another version is left there: it must be
/// refused as `IncompatibleService`, naming `service` and the `payload` this version expects.
fn refused_as_incompatible(names: &ServiceNames, service: &str, payload: &str) -> IpcSetupError {
    let err = RtIpc::create(names)
        .err()
        .expect("the stale service is refused");
    match &err {
        IpcSetupError::IncompatibleService {
            name, payload: p, ..
        } => {
            assert_eq!(name, service);
            assert_eq!(*p, payload);
        }
        other => panic!("not IncompatibleService: {other:?}"),
    }
    err
}

#[test]
fn a_stale_state_service_of_another_version_is_named_as_such() {
    let names = names("stale-state");
    let node = node();
    let _old = node
        .service_builder(&names.state_service())
        .blackboard_creator::<u32>()
        .max_readers(STATE_MAX_READERS)
        .add::<OldStateSample>(STATE_KEY, OldStateSample::default())
        .create()
        .unwrap();
    let err = refused_as_incompatible(&names, &names.state(), "mcm.StateSample.v7");
    assert!(
        matches!(
            err,
            IpcSetupError::IncompatibleService {
                source: Incompatibility::StateEntry(EntryHandleMutError::EntryDoesNotExist),
                ..
            }
        ),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(
        text.contains(&names.state()) && text.contains("another version"),
        "{text}"
    );
}

#[test]
fn a_stale_command_service_of_another_version_is_named_as_such() {
    let names = names("stale-command");
    let node = node();
    let _old = node
        .service_builder(&names.command_service())
        .publish_subscribe::<OldCommandSample>()
        .create()
        .unwrap();
    let err = refused_as_incompatible(&names, &names.command(), "mcm.CommandSample.v1");
    assert!(
        matches!(
            err,
            IpcSetupError::IncompatibleService {
                source: Incompatibility::CommandService(
                    PublishSubscribeOpenError::IncompatibleTypes
                ),
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn a_second_core_of_the_same_instance_is_refused() {
    let names = names("in-use");
    let _first = RtIpc::create(&names).expect("the first core sets up");
    let err = RtIpc::create(&names).err().expect("the second is refused");
    match &err {
        IpcSetupError::InstanceInUse {
            instance,
            source: PortTaken::Writer(_),
            ..
        } => assert_eq!(instance, names.instance()),
        other => panic!("not InstanceInUse: {other:?}"),
    }
    assert!(err.to_string().contains("another mcm-rt runs"), "{err}");
}

#[test]
fn a_restarted_core_opens_the_services_its_peers_keep() {
    let names = names("restart");
    let first = RtIpc::create(&names).expect("the first core sets up");
    // A peer keeps the command service open while the core restarts.
    let node = node();
    let _peer = node
        .service_builder(&names.command_service())
        .publish_subscribe::<mcm_shared::sample::CommandSample>()
        .open()
        .unwrap();
    drop(first);
    RtIpc::create(&names).expect("the restarted core opens them again");
}

#[test]
fn a_listener_wakes_after_each_published_state_and_across_a_restart() {
    let names = names("state-event");
    let core = RtIpc::create(&names).expect("the core sets up");
    let node = node();
    let listener = state_listener(&node, &names);
    let wait = |listener: &iceoryx2::port::listener::Listener<ipc::Service>| {
        let mut ids = Vec::new();
        listener
            .timed_wait(|e| ids.push(e.id.as_value()), Duration::from_secs(5))
            .unwrap();
        ids
    };
    let mut state = mcm_shared::sample::StateSample::default();
    for seq in 1..=3 {
        state.seq = seq;
        core.publish(&state);
        core.notify_state().unwrap();
        assert_eq!(wait(&listener), [STATE_EVENT_ID], "cycle {seq}");
    }
    // Nothing more until the next state.
    let mut extra = 0;
    listener.try_wait(|_| extra += 1).unwrap();
    assert_eq!(extra, 0);
    // The listener keeps the event service while the core restarts: it opens it again.
    drop(core);
    let core = RtIpc::create(&names).expect("the restarted core opens the event");
    core.notify_state().unwrap();
    assert_eq!(wait(&listener), [STATE_EVENT_ID]);
}
