//! Opening an MCM's shared memory that is missing or of another version: the client names the
//! problem instead of passing iceoryx2's `DoesNotExist` / `EntryDoesNotExist` on. The "core"
//! here is a stand-in that creates the services with other sample types, under a unique
//! instance name.

use iceoryx2::prelude::*;
use mcm_client::shm::ports::Peer;
use mcm_client::shm::{LayoutMismatch, OpenError, ShmClient};
use mcm_shared::sample::{CommandSample, REPLY_BLOCKS, ReplyBlock};
use mcm_shared::service::{STATE_KEY, ServiceNames};

/// A state sample of an older layout: another name and size.
#[derive(Debug, Clone, Copy, Default, ZeroCopySend)]
#[repr(C)]
#[type_name("mcm.StateSample.v3")]
struct OldState {
    seq: u64,
    t_ns: u64,
}

/// A command sample of another version.
#[derive(Debug, Clone, Copy, Default, ZeroCopySend)]
#[repr(C)]
#[type_name("mcm.CommandSample.v0")]
struct OldCommand {
    client_id: u64,
    kind: u32,
    flags: u32,
}

fn instance(tag: &str) -> String {
    format!("co{}-{tag}", std::process::id())
}

fn node() -> Node<ipc::Service> {
    set_log_level(LogLevel::Error);
    NodeBuilder::new()
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .unwrap()
}

fn err(instance: &str) -> OpenError {
    match ShmClient::connect(instance) {
        Ok(_) => panic!("connect to {instance} should fail"),
        Err(e) => e,
    }
}

#[test]
fn an_instance_that_is_not_running_says_so() {
    let name = instance("none");
    let e = err(&name);
    assert!(matches!(e, OpenError::NotRunning { .. }), "{e:?}");
    assert!(
        e.to_string()
            .contains(&format!("instance {name:?} is not running")),
        "{e}"
    );
    assert!(matches!(err("bad/name"), OpenError::InstanceName(_)));
}

#[test]
fn a_state_entry_of_another_version_is_named_with_what_the_client_expects() {
    let name = instance("oldstate");
    let names = ServiceNames::new(&name).unwrap();
    let n = node();
    let mut creator = n
        .service_builder(&names.state_service())
        .blackboard_creator::<u32>()
        .add::<OldState>(STATE_KEY, OldState::default());
    for key in 1..=REPLY_BLOCKS as u32 {
        creator = creator.add::<ReplyBlock>(key, ReplyBlock::default());
    }
    let _board = creator.create().unwrap();
    let e = err(&name);
    let OpenError::Incompatible {
        service,
        peer,
        mismatch,
        expected,
    } = &e
    else {
        panic!("{e:?}")
    };
    assert_eq!((service, *peer), (&names.state(), Peer::Client));
    assert!(
        matches!(
            mismatch,
            LayoutMismatch::Entry {
                key: 0,
                present: true,
                ..
            }
        ),
        "{mismatch:?}"
    );
    assert_eq!(
        mismatch.to_string(),
        "its state entry (key 0) is of another type, size or alignment"
    );
    assert_eq!(expected, "`mcm.StateSample.v7`, 1040 bytes, alignment 8");
    assert!(
        e.to_string()
            .contains("build the client from the same MCM version"),
        "{e}"
    );
}

#[test]
fn a_command_service_of_another_version_names_the_cores_payload() {
    let name = instance("oldcmd");
    let names = ServiceNames::new(&name).unwrap();
    let n = node();
    let mut creator = n
        .service_builder(&names.state_service())
        .blackboard_creator::<u32>()
        .add::<mcm_shared::sample::StateSample>(STATE_KEY, Default::default());
    for key in 1..=REPLY_BLOCKS as u32 {
        creator = creator.add::<ReplyBlock>(key, ReplyBlock::default());
    }
    let _board = creator.create().unwrap();
    let _commands = n
        .service_builder(&names.command_service())
        .publish_subscribe::<OldCommand>()
        .create()
        .unwrap();
    let e = err(&name);
    let OpenError::Incompatible {
        service,
        mismatch,
        expected,
        ..
    } = &e
    else {
        panic!("{e:?}")
    };
    assert_eq!(service, &names.command());
    assert!(
        matches!(mismatch, LayoutMismatch::CommandPayload { .. }),
        "{mismatch:?}"
    );
    assert_eq!(
        mismatch.to_string(),
        "its payload is `mcm.CommandSample.v0`, 16 bytes, alignment 8"
    );
    assert_eq!(
        expected,
        &mcm_client::shm::describe::<CommandSample>(),
        "the client's own type"
    );
}

#[test]
fn a_state_board_without_reply_blocks_says_how_many_keys_it_has() {
    let name = instance("noreplies");
    let names = ServiceNames::new(&name).unwrap();
    let n = node();
    let _board = n
        .service_builder(&names.state_service())
        .blackboard_creator::<u32>()
        .add::<mcm_shared::sample::StateSample>(STATE_KEY, Default::default())
        .create()
        .unwrap();
    let e = err(&name);
    let OpenError::Incompatible {
        mismatch, expected, ..
    } = &e
    else {
        panic!("{e:?}")
    };
    assert!(
        matches!(
            mismatch,
            LayoutMismatch::Entry {
                key: 1,
                present: false,
                keys: 1,
                ..
            }
        ),
        "{mismatch:?}"
    );
    assert_eq!(
        mismatch.to_string(),
        format!(
            "it has no reply block (key 1); it has 1 keys, {} expected",
            REPLY_BLOCKS + 1
        )
    );
    assert_eq!(expected, &mcm_client::shm::describe::<ReplyBlock>());
}
