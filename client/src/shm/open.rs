//! Opening the real-time core's services, with the versions checked: iceoryx2 compares only a
//! type's name, size and alignment, and a blackboard entry of another type reads as
//! `EntryDoesNotExist`; this module turns each mismatch into an [`ShmError::Incompatible`]
//! that names the service, what differs and what this client expects.

use super::error::ShmError;
use iceoryx2::config::Config;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::reader::EntryHandle;
use iceoryx2::prelude::*;
use iceoryx2::service::builder::blackboard::BlackboardOpenError;
use iceoryx2::service::builder::event::EventOpenError;
use iceoryx2::service::builder::publish_subscribe::PublishSubscribeOpenError;
use mcm_shared::sample::{CommandSample, REPLY_BLOCKS, ReplyBlock, ReplyEntries, StateSample};
use mcm_shared::service::{STATE_KEY, ServiceNames};

/// The ports of one client.
pub(super) struct Ports {
    pub(super) state: EntryHandle<ipc::Service, u32, StateSample>,
    pub(super) replies: ReplyEntries,
    pub(super) publisher: Publisher<ipc::Service, CommandSample, ()>,
    pub(super) listener: Listener<ipc::Service>,
    // Dropped last: the ports above live in the node.
    pub(super) _node: Node<ipc::Service>,
}

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

fn ipc_err(step: impl Into<String>) -> impl FnOnce(String) -> ShmError {
    let step = step.into();
    move |problem| ShmError::Ipc { step, problem }
}

fn service_name(name: &str) -> Result<ServiceName, ShmError> {
    ServiceName::new(name).map_err(|e| ShmError::Ipc {
        step: format!("the service name `{name}`"),
        problem: format!("{e}"),
    })
}

/// Open the services of `names` and create this client's ports.
pub(super) fn open(names: &ServiceNames) -> Result<Ports, ShmError> {
    set_log_level_from_env_or(LogLevel::Error);
    let instance = names.instance().to_string();
    let node_name = names.node("mcm-client");
    let node = NodeBuilder::new()
        .name(&NodeName::new(&node_name).map_err(|e| ShmError::Ipc {
            step: format!("the node name `{node_name}`"),
            problem: format!("{e:?}"),
        })?)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .map_err(|e| ipc_err("creating the client's iceoryx2 node")(format!("{e:?}")))?;
    let not_running = |service: &str| ShmError::NotRunning {
        instance: instance.clone(),
        service: service.to_string(),
    };

    // The state blackboard: key 0 the state, keys 1..=REPLY_BLOCKS the reply blocks.
    let state_name = names.state();
    let board = node
        .service_builder(&service_name(&state_name)?)
        .blackboard_opener::<u32>()
        .open()
        .map_err(|e| match e {
            BlackboardOpenError::DoesNotExist => not_running(&state_name),
            BlackboardOpenError::IncompatibleKeys => ShmError::Incompatible {
                service: state_name.clone(),
                problem: "its key type is not u32".into(),
                expected: describe::<StateSample>(),
            },
            e => ipc_err(format!("opening `{state_name}`"))(format!("{e:?}")),
        })?;
    let reader = board
        .reader_builder()
        .create()
        .map_err(|e| ipc_err(format!("a reader of `{state_name}`"))(format!("{e:?}")))?;
    let mut keys = Vec::new();
    board.list_keys(|k| {
        keys.push(*k);
        CallbackProgression::Continue
    });
    let mismatch = |what: &str, key: u32, expected: String| ShmError::Incompatible {
        service: state_name.clone(),
        problem: if keys.contains(&key) {
            format!(
                "its {what} (key {key}) is of another type, size or alignment than this client's"
            )
        } else {
            format!(
                "it has no {what} (key {key}); it has {} keys, this client expects {}",
                keys.len(),
                REPLY_BLOCKS + 1
            )
        },
        expected,
    };
    let state = reader
        .entry::<StateSample>(&STATE_KEY)
        .map_err(|_| mismatch("state entry", STATE_KEY, describe::<StateSample>()))?;
    let replies = mcm_shared::sample::open_reply_entries(&reader)
        .map_err(|e| mismatch("reply block", e.key, describe::<ReplyBlock>()))?;

    // The command service.
    let command_name = names.command();
    let commands = node
        .service_builder(&service_name(&command_name)?)
        .publish_subscribe::<CommandSample>()
        .open()
        .map_err(|e| match e {
            PublishSubscribeOpenError::DoesNotExist => not_running(&command_name),
            PublishSubscribeOpenError::IncompatibleTypes => ShmError::Incompatible {
                service: command_name.clone(),
                problem: found_payload(&command_name),
                expected: describe::<CommandSample>(),
            },
            e => ipc_err(format!("opening `{command_name}`"))(format!("{e:?}")),
        })?;
    let publisher = commands.publisher_builder().create().map_err(|e| {
        ipc_err(format!(
            "a publisher on `{command_name}` (at most {} publishers: the gateway and up to {} controllers)",
            mcm_shared::service::COMMAND_MAX_PUBLISHERS,
            mcm_shared::service::COMMAND_MAX_PUBLISHERS - 1
        ))(format!("{e:?}"))
    })?;

    // The state event, notified after each new state.
    let event_name = names.state_event();
    let listener = node
        .service_builder(&service_name(&event_name)?)
        .event()
        .open()
        .map_err(|e| match e {
            EventOpenError::DoesNotExist => not_running(&event_name),
            e => ipc_err(format!("opening `{event_name}`"))(format!("{e:?}")),
        })?
        .listener_builder()
        .create()
        .map_err(|e| ipc_err(format!("a listener of `{event_name}`"))(format!("{e:?}")))?;
    Ok(Ports {
        state,
        replies,
        publisher,
        listener,
        _node: node,
    })
}

/// The payload type the running core's command service carries, in words.
fn found_payload(service: &str) -> String {
    let details = ServiceName::new(service).ok().and_then(|name| {
        ipc::Service::details(
            &name,
            Config::global_config(),
            MessagingPattern::PublishSubscribe,
        )
        .ok()
        .flatten()
    });
    match details {
        Some(d) => {
            let p = &d
                .static_details
                .publish_subscribe()
                .message_type_details()
                .payload;
            format!(
                "its payload is `{}`, {} bytes, alignment {}",
                p.type_name(),
                p.size(),
                p.alignment()
            )
        }
        None => "its payload type is another than this client's".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_expected_types_are_named_with_their_version_and_size() {
        assert_eq!(
            describe::<StateSample>(),
            "`mcm.StateSample.v4`, 768 bytes, alignment 8"
        );
        assert_eq!(
            describe::<CommandSample>(),
            "`mcm.CommandSample.v1`, 536 bytes, alignment 8"
        );
    }
}
