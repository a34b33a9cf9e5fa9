//! The iceoryx2 edge of the real-time core: the state blackboard it writes, the command
//! service it drains and the state event it notifies after each cycle.
//!
//! Set-up ([`RtIpc::create`]) runs once before the cycle. Inside the cycle, [`RtIpc::drain`]
//! (`Subscriber::receive`), [`RtIpc::publish`] (blackboard `update_with_copy`) and
//! [`RtIpc::notify_state`] (`Notifier::notify`: a bit in shared memory and, only when a listener is
//! idle, one non-blocking `sendto`) neither block nor allocate in steady state. When a peer opens
//! or closes the command service, the next `receive` sets the connection up inside that call
//! (iceoryx2 0.10: about ten small allocations and 0.1 to 0.3 ms); peers therefore join at
//! start-up, not per command. State goes through a blackboard precisely because readers joining or
//! leaving never touch the writer.
//!
//! The real-time core *creates* the services with the QoS of [`mcm_shared::service`]; anything
//! else opens them. Set-up errors keep iceoryx2's own error as their source, one variant per
//! step; two causes get their own words: services of the same name left by an MCM of another
//! version ([`IpcSetupError::IncompatibleService`]) and a second live `mcm-rt` of the same
//! instance ([`IpcSetupError::InstanceInUse`]).

use iceoryx2::node::NodeCreationFailure;
use iceoryx2::port::notifier::{Notifier, NotifierCreateError, NotifierNotifyError};
use iceoryx2::port::subscriber::{Subscriber, SubscriberCreateError};
use iceoryx2::port::writer::{EntryHandleMut, EntryHandleMutError, WriterCreateError};
use iceoryx2::prelude::*;
use iceoryx2::service::builder::blackboard::{BlackboardCreateError, BlackboardOpenError};
use iceoryx2::service::builder::event::{EventOpenError, EventOpenOrCreateError};
use iceoryx2::service::builder::publish_subscribe::{
    PublishSubscribeOpenError, PublishSubscribeOpenOrCreateError,
};
use mcm_shared::sample::{
    CommandSample, REPLY_BLOCKS, Reply, ReplyBlock, StateSample, reply_location,
};
use mcm_shared::service::{
    COMMAND_BUFFER, COMMAND_MAX_PUBLISHERS, STATE_EVENT_ID, STATE_EVENT_MAX_LISTENERS, STATE_KEY,
    STATE_MAX_READERS, ServiceNames,
};

/// Setting up the IPC services failed: which step, on which name, and iceoryx2's own error.
#[derive(Debug, thiserror::Error)]
pub enum IpcSetupError {
    #[error("iceoryx2 refuses the node name `{name}`: {source}")]
    NodeName {
        name: String,
        #[source]
        source: SemanticStringError,
    },
    #[error("cannot create the iceoryx2 node `{name}`: {source}")]
    Node {
        name: String,
        #[source]
        source: NodeCreationFailure,
    },
    #[error("cannot create the state blackboard `{name}`: {source}")]
    StateCreate {
        name: String,
        #[source]
        source: BlackboardCreateError,
    },
    #[error("cannot open the existing state blackboard `{name}`: {source}")]
    StateOpen {
        name: String,
        #[source]
        source: BlackboardOpenError,
    },
    #[error("cannot create the writer of the state blackboard `{name}`: {source}")]
    Writer {
        name: String,
        #[source]
        source: WriterCreateError,
    },
    #[error("cannot take the state entry (key {key}) of the blackboard `{name}`: {source}")]
    Entry {
        name: String,
        key: u32,
        #[source]
        source: EntryHandleMutError,
    },
    #[error("cannot open or create the command service `{name}`: {source}")]
    CommandService {
        name: String,
        #[source]
        source: PublishSubscribeOpenOrCreateError,
    },
    #[error("cannot create the subscriber of the command service `{name}`: {source}")]
    Subscriber {
        name: String,
        #[source]
        source: SubscriberCreateError,
    },
    #[error("cannot open or create the state event `{name}`: {source}")]
    StateEvent {
        name: String,
        #[source]
        source: EventOpenOrCreateError,
    },
    #[error("cannot create the notifier of the state event `{name}`: {source}")]
    Notifier {
        name: String,
        #[source]
        source: NotifierCreateError,
    },
    #[error(
        "the service `{name}` exists with another payload type, layout or QoS than this mcm-rt's \
         `{payload}`: it was left by an MCM of another version ({source}); stop the processes \
         of that version (gateway, controllers, mcm-rt) so that the service goes away, or use \
         another instance name"
    )]
    IncompatibleService {
        name: String,
        /// The payload this version expects (its iceoryx2 type name).
        payload: &'static str,
        #[source]
        source: Incompatibility,
    },
    #[error(
        "the services of instance `{instance}` exist already: another mcm-rt runs with this \
         instance name ({name}: {source})"
    )]
    InstanceInUse {
        instance: String,
        name: String,
        #[source]
        source: PortTaken,
    },
}

/// How a service of the same name differs from what this version creates.
#[derive(Debug, thiserror::Error)]
pub enum Incompatibility {
    /// The blackboard has another key type or QoS.
    #[error("{0}")]
    StateService(#[from] BlackboardOpenError),
    /// The blackboard has no entry of key [`STATE_KEY`] with this version's `StateSample`.
    #[error("no state entry of this type: {0}")]
    StateEntry(#[from] EntryHandleMutError),
    /// The command service has another payload type or QoS.
    #[error("{0}")]
    CommandService(#[from] PublishSubscribeOpenError),
    /// The state event has another pattern, attributes or limits.
    #[error("{0}")]
    StateEvent(#[from] EventOpenError),
}

/// The single port only one `mcm-rt` per instance may hold is held already.
#[derive(Debug, thiserror::Error)]
pub enum PortTaken {
    #[error("the state writer is taken: {0}")]
    Writer(#[from] WriterCreateError),
    #[error("the command subscriber is taken: {0}")]
    Subscriber(#[from] SubscriberCreateError),
    #[error("the state event's notifier is taken: {0}")]
    Notifier(#[from] NotifierCreateError),
}

/// Receiving commands failed inside the cycle (the cycle goes on; the runner counts it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("receiving from the command service failed: {0}")]
pub struct ReceiveError(#[from] pub iceoryx2::port::ReceiveError);

/// What one [`RtIpc::drain`] gave: the samples received before an error stay received.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Drained {
    pub count: usize,
    pub error: Option<ReceiveError>,
}

/// Notifying the state event failed inside the cycle (the runner counts it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("notifying the state event failed: {0:?}")]
pub struct NotifyError(pub NotifierNotifyError);

/// The iceoryx2 type name of `T` (what a stale service of another version differs in).
fn payload_name<T: ZeroCopySend>() -> &'static str {
    // SAFETY: only reads the name the type declares; nothing is sent or received here, so no
    // layout is relied upon.
    unsafe { <T as ZeroCopySend>::type_name() }
}

/// The real-time core's IPC ports. Not `Send`: create it on the cycle thread.
pub struct RtIpc {
    _node: Node<ipc::Service>,
    state: EntryHandleMut<ipc::Service, u32, StateSample>,
    /// The reply blocks, by key - 1 (set up once; the cycle only updates them).
    reply_blocks: Vec<EntryHandleMut<ipc::Service, u32, ReplyBlock>>,
    /// The block being filled and its key (0: none yet).
    block: ReplyBlock,
    block_key: u32,
    commands: Subscriber<ipc::Service, CommandSample, ()>,
    state_event: Notifier<ipc::Service>,
}

impl RtIpc {
    /// Create the node and the services of `names`.
    pub fn create(names: &ServiceNames) -> Result<Self, IpcSetupError> {
        // iceoryx2 warns about its own defaults (no config file); IOX2_LOG_LEVEL overrides.
        set_log_level_from_env_or(LogLevel::Error);
        let node_name = names.node("mcm-rt");
        let node = NodeBuilder::new()
            .name(
                &node_name
                    .as_str()
                    .try_into()
                    .map_err(|source| IpcSetupError::NodeName {
                        name: node_name.clone(),
                        source,
                    })?,
            )
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<ipc::Service>()
            .map_err(|source| IpcSetupError::Node {
                name: node_name.clone(),
                source,
            })?;
        let (state, reply_blocks) = state_entries(&node, names)?;
        let commands = command_subscriber(&node, names)?;
        let state_event = state_notifier(&node, names)?;
        Ok(Self {
            _node: node,
            state,
            reply_blocks,
            block: ReplyBlock::default(),
            block_key: 0,
            commands,
            state_event,
        })
    }

    /// Move up to `buf.len()` pending commands into `buf` and say how many. Commands beyond
    /// that stay queued for the next cycle. A receive error ends the drain; the commands
    /// received before it are kept (the caller counts the error).
    pub fn drain(&mut self, buf: &mut [CommandSample]) -> Drained {
        let mut count = 0;
        while count < buf.len() {
            match self.commands.receive() {
                Ok(Some(sample)) => {
                    buf[count] = *sample;
                    count += 1;
                }
                Ok(None) => break,
                Err(e) => {
                    return Drained {
                        count,
                        error: Some(ReceiveError(e)),
                    };
                }
            }
        }
        Drained { count, error: None }
    }

    /// Tell the state event's listeners that a new state is published (event id
    /// [`STATE_EVENT_ID`]). Call after [`RtIpc::publish`].
    pub fn notify_state(&self) -> Result<(), NotifyError> {
        self.state_event.notify().map(|_| ()).map_err(NotifyError)
    }

    /// Publish the replies of this cycle, numbered from `first_seq` and stamped with `cycle`,
    /// into their blocks. Call before [`RtIpc::publish`] of the state that counts them in its
    /// `reply_head`, so that a reader that sees the head finds every reply up to it.
    pub fn publish_replies(&mut self, first_seq: u64, cycle: u64, replies: &[Reply]) {
        if replies.is_empty() {
            return;
        }
        for (i, r) in replies.iter().enumerate() {
            let seq = first_seq + i as u64;
            let (key, slot) = reply_location(seq);
            if key != self.block_key {
                self.flush_block();
                self.block = ReplyBlock::default();
                self.block_key = key;
            }
            self.block.replies[slot] = Reply { seq, cycle, ..*r };
        }
        self.flush_block();
    }

    fn flush_block(&self) {
        if let Some(entry) = (self.block_key as usize)
            .checked_sub(1)
            .and_then(|i| self.reply_blocks.get(i))
        {
            entry.update_with_copy(self.block);
        }
    }

    /// Publish the state of this cycle.
    pub fn publish(&self, state: &StateSample) {
        self.state.update_with_copy(*state);
    }
}

/// The state blackboard's entries (the state, and the reply blocks under keys 1 to
/// [`REPLY_BLOCKS`]), the blackboard created or (after a restart) opened.
///
/// A restarted mcm-rt finds its services still open by the gateway or controllers: it creates
/// them when they are missing and opens them otherwise. A second live mcm-rt of the same
/// instance is refused when it asks for the single writer.
#[allow(clippy::type_complexity)]
fn state_entries(
    node: &Node<ipc::Service>,
    names: &ServiceNames,
) -> Result<
    (
        EntryHandleMut<ipc::Service, u32, StateSample>,
        Vec<EntryHandleMut<ipc::Service, u32, ReplyBlock>>,
    ),
    IpcSetupError,
> {
    let name = names.state();
    let incompatible = |source: Incompatibility| IpcSetupError::IncompatibleService {
        name: name.clone(),
        payload: payload_name::<StateSample>(),
        source,
    };
    let service_name = names.state_service();
    let mut creator = node
        .service_builder(&service_name)
        .blackboard_creator::<u32>()
        .max_readers(STATE_MAX_READERS)
        .add::<StateSample>(STATE_KEY, StateSample::default());
    for key in 1..=REPLY_BLOCKS as u32 {
        creator = creator.add::<ReplyBlock>(key, ReplyBlock::default());
    }
    let service = match creator.create() {
        Ok(s) => s,
        Err(BlackboardCreateError::AlreadyExists) => node
            .service_builder(&service_name)
            .blackboard_opener::<u32>()
            .max_readers(STATE_MAX_READERS)
            .open()
            .map_err(|source| match source {
                BlackboardOpenError::IncompatibleKeys
                | BlackboardOpenError::IncompatibleAttributes
                | BlackboardOpenError::IncompatibleMessagingPattern
                | BlackboardOpenError::DoesNotSupportRequestedAmountOfReaders => {
                    incompatible(source.into())
                }
                _ => IpcSetupError::StateOpen {
                    name: name.clone(),
                    source,
                },
            })?,
        Err(source) => {
            return Err(IpcSetupError::StateCreate {
                name: name.clone(),
                source,
            });
        }
    };
    let writer = service
        .writer_builder()
        .create()
        .map_err(|source| match source {
            WriterCreateError::ExceedsMaxSupportedWriters => IpcSetupError::InstanceInUse {
                instance: names.instance().to_string(),
                name: name.clone(),
                source: source.into(),
            },
            _ => IpcSetupError::Writer {
                name: name.clone(),
                source,
            },
        })?;
    let entry_error = |key: u32| {
        let name = name.clone();
        move |source| match source {
            // The entry exists only with this key *and* this value type.
            EntryHandleMutError::EntryDoesNotExist => IpcSetupError::IncompatibleService {
                name,
                payload: payload_name::<StateSample>(),
                source: Incompatibility::StateEntry(source),
            },
            _ => IpcSetupError::Entry { name, key, source },
        }
    };
    let state = writer
        .entry::<StateSample>(&STATE_KEY)
        .map_err(entry_error(STATE_KEY))?;
    let blocks = (1..=REPLY_BLOCKS as u32)
        .map(|key| writer.entry::<ReplyBlock>(&key).map_err(entry_error(key)))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((state, blocks))
}

/// The command service (opened or created) and its single subscriber.
fn command_subscriber(
    node: &Node<ipc::Service>,
    names: &ServiceNames,
) -> Result<Subscriber<ipc::Service, CommandSample, ()>, IpcSetupError> {
    let name = names.command();
    let service = node
        .service_builder(&names.command_service())
        .publish_subscribe::<CommandSample>()
        .max_publishers(COMMAND_MAX_PUBLISHERS)
        .max_subscribers(1)
        .subscriber_max_buffer_size(COMMAND_BUFFER)
        .history_size(0)
        .enable_safe_overflow(true)
        .open_or_create()
        .map_err(|source| match source {
            PublishSubscribeOpenOrCreateError::PublishSubscribeOpenError(
                e @ (PublishSubscribeOpenError::IncompatibleTypes
                | PublishSubscribeOpenError::IncompatibleAttributes
                | PublishSubscribeOpenError::IncompatibleMessagingPattern
                | PublishSubscribeOpenError::IncompatibleOverflowBehavior
                | PublishSubscribeOpenError::DoesNotSupportRequestedMinBufferSize
                | PublishSubscribeOpenError::DoesNotSupportRequestedMinHistorySize
                | PublishSubscribeOpenError::DoesNotSupportRequestedAmountOfPublishers
                | PublishSubscribeOpenError::DoesNotSupportRequestedAmountOfSubscribers
                | PublishSubscribeOpenError::VersionMismatch),
            ) => IpcSetupError::IncompatibleService {
                name: name.clone(),
                payload: payload_name::<CommandSample>(),
                source: e.into(),
            },
            _ => IpcSetupError::CommandService {
                name: name.clone(),
                source,
            },
        })?;
    service
        .subscriber_builder()
        .buffer_size(COMMAND_BUFFER)
        .create()
        .map_err(|source| match source {
            SubscriberCreateError::ExceedsMaxSupportedSubscribers => IpcSetupError::InstanceInUse {
                instance: names.instance().to_string(),
                name: name.clone(),
                source: source.into(),
            },
            _ => IpcSetupError::Subscriber {
                name: name.clone(),
                source,
            },
        })
}

/// The state event (opened or created) and its single notifier.
fn state_notifier(
    node: &Node<ipc::Service>,
    names: &ServiceNames,
) -> Result<Notifier<ipc::Service>, IpcSetupError> {
    let name = names.state_event();
    let service = node
        .service_builder(&names.state_event_service())
        .event()
        .max_listeners(STATE_EVENT_MAX_LISTENERS)
        .max_notifiers(1)
        .open_or_create()
        .map_err(|source| match source {
            EventOpenOrCreateError::EventOpenError(
                e @ (EventOpenError::IncompatibleMessagingPattern
                | EventOpenError::IncompatibleAttributes
                | EventOpenError::DoesNotSupportRequestedAmountOfNotifiers
                | EventOpenError::DoesNotSupportRequestedAmountOfListeners),
            ) => IpcSetupError::IncompatibleService {
                name: name.clone(),
                payload: "event",
                source: e.into(),
            },
            _ => IpcSetupError::StateEvent {
                name: name.clone(),
                source,
            },
        })?;
    service
        .notifier_builder()
        .default_event_id(EventId::new(STATE_EVENT_ID))
        .create()
        .map_err(|source| match source {
            NotifierCreateError::ExceedsMaxSupportedNotifiers => IpcSetupError::InstanceInUse {
                instance: names.instance().to_string(),
                name: name.clone(),
                source: source.into(),
            },
            _ => IpcSetupError::Notifier {
                name: name.clone(),
                source,
            },
        })
}
