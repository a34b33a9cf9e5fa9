//! Opening the core's services with the versions checked: iceoryx2 compares only a type's name,
//! size and alignment, and a blackboard entry of another type reads as `EntryDoesNotExist`; each
//! mismatch becomes an [`OpenError::Incompatible`] that names the service, what differs and
//! what this build expects.

use super::Peer;
use super::error::{Entry, LayoutMismatch, OpenError, ServiceOpenError};
use iceoryx2::config::Config;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::reader::EntryHandle;
use iceoryx2::prelude::*;
use iceoryx2::service::builder::blackboard::BlackboardOpenError;
use iceoryx2::service::builder::publish_subscribe::PublishSubscribeOpenError;
use mcm_shared::sample::{
    CommandSample, ReplyBlock, ReplyEntries, StateSample, open_reply_entries,
};
use mcm_shared::service::{STATE_KEY, ServiceNames};

/// `name` (size bytes, align bytes) of a sample type, as iceoryx2 compares it.
pub fn describe<T: ZeroCopySend>() -> String {
    // SAFETY: `type_name` is `unsafe` only because implementors promise a unique name; calling
    // it has no precondition.
    let name = unsafe { <T as ZeroCopySend>::type_name() };
    format!(
        "`{name}`, {} bytes, alignment {}",
        core::mem::size_of::<T>(),
        core::mem::align_of::<T>()
    )
}

/// An iceoryx2 node named `<role>.<instance>`, without iceoryx2's signal handling (the program
/// keeps its own). iceoryx2 logs errors only, unless `IOX2_LOG_LEVEL` says otherwise.
pub fn open_node(names: &ServiceNames, role: &str) -> Result<Node<ipc::Service>, OpenError> {
    set_log_level_from_env_or(LogLevel::Error);
    let name = names.node(role);
    let node_name = NodeName::new(&name).map_err(|source| OpenError::NodeName {
        name: name.clone(),
        source,
    })?;
    NodeBuilder::new()
        .name(&node_name)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .map_err(|source| OpenError::Node { name, source })
}

/// The error of opening `service`: not running when it does not exist.
fn open_failed(names: &ServiceNames, service: &str, source: ServiceOpenError) -> OpenError {
    if source.does_not_exist() {
        OpenError::NotRunning {
            instance: names.instance().to_string(),
            service: service.to_string(),
            source,
        }
    } else {
        OpenError::Service {
            service: service.to_string(),
            source,
        }
    }
}

/// The state blackboard: key [`STATE_KEY`] the state, keys 1 to `REPLY_BLOCKS` the reply blocks.
pub(super) fn state(
    node: &Node<ipc::Service>,
    names: &ServiceNames,
    peer: Peer,
) -> Result<(EntryHandle<ipc::Service, u32, StateSample>, ReplyEntries), OpenError> {
    let service = names.state();
    let incompatible = |mismatch, expected| OpenError::Incompatible {
        service: service.clone(),
        peer,
        mismatch,
        expected,
    };
    let board = node
        .service_builder(&names.state_service())
        .blackboard_opener::<u32>()
        .open()
        .map_err(|e| match e {
            BlackboardOpenError::IncompatibleKeys => {
                incompatible(LayoutMismatch::StateKey(e), describe::<StateSample>())
            }
            e => open_failed(names, &service, e.into()),
        })?;
    let reader = board
        .reader_builder()
        .create()
        .map_err(|source| OpenError::Reader {
            service: service.clone(),
            source,
        })?;
    let mut keys = Vec::new();
    board.list_keys(|k| {
        keys.push(*k);
        CallbackProgression::Continue
    });
    // The core adds every entry when it creates the service, so an entry that does not open is
    // one of another type, or one an MCM of another version does not have.
    let mismatch = |entry, key, source| LayoutMismatch::Entry {
        entry,
        key,
        present: keys.contains(&key),
        keys: keys.len(),
        source,
    };
    let state = reader.entry::<StateSample>(&STATE_KEY).map_err(|e| {
        incompatible(
            mismatch(Entry::State, STATE_KEY, e),
            describe::<StateSample>(),
        )
    })?;
    let replies = open_reply_entries(&reader).map_err(|e| {
        incompatible(
            mismatch(Entry::ReplyBlock, e.key, e.source),
            describe::<ReplyBlock>(),
        )
    })?;
    Ok((state, replies))
}

/// A publisher on the command service.
pub(super) fn publisher(
    node: &Node<ipc::Service>,
    names: &ServiceNames,
    peer: Peer,
) -> Result<Publisher<ipc::Service, CommandSample, ()>, OpenError> {
    let service = names.command();
    node.service_builder(&names.command_service())
        .publish_subscribe::<CommandSample>()
        .open()
        .map_err(|e| match e {
            PublishSubscribeOpenError::IncompatibleTypes => OpenError::Incompatible {
                service: service.clone(),
                peer,
                mismatch: LayoutMismatch::CommandPayload {
                    found: found_payload(&names.command_service()),
                    source: e,
                },
                expected: describe::<CommandSample>(),
            },
            e => open_failed(names, &service, e.into()),
        })?
        .publisher_builder()
        .create()
        .map_err(|source| OpenError::Publisher { service, source })
}

/// A listener of the state event (notified by the core after each new state), through `node`.
pub fn open_state_event(
    node: &Node<ipc::Service>,
    names: &ServiceNames,
) -> Result<Listener<ipc::Service>, OpenError> {
    let service = names.state_event();
    node.service_builder(&names.state_event_service())
        .event()
        .open()
        .map_err(|e| open_failed(names, &service, e.into()))?
        .listener_builder()
        .create()
        .map_err(|source| OpenError::Listener { service, source })
}

/// The payload type the running core's command service carries, in words, when iceoryx2 can
/// tell.
fn found_payload(service: &ServiceName) -> Option<String> {
    let details = ipc::Service::details(
        service,
        Config::global_config(),
        MessagingPattern::PublishSubscribe,
    )
    .ok()
    .flatten()?;
    let p = &details
        .static_details
        .publish_subscribe()
        .message_type_details()
        .payload;
    Some(format!(
        "`{}`, {} bytes, alignment {}",
        p.type_name(),
        p.size(),
        p.alignment()
    ))
}
