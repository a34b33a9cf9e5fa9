//! Opening the real-time core's services: the state blackboard (read) and the command service
//! (publish). Each step's failure keeps iceoryx2's own error; a service that does not exist
//! means the core is not running, a service of another layout means the gateway and the core
//! were built from different versions.

use iceoryx2::node::NodeCreationFailure;
use iceoryx2::port::publisher::{Publisher, PublisherCreateError};
use iceoryx2::port::reader::{EntryHandle, EntryHandleError, ReaderCreateError};
use iceoryx2::prelude::*;
use iceoryx2::service::builder::blackboard::BlackboardOpenError;
use iceoryx2::service::builder::publish_subscribe::PublishSubscribeOpenError;
use iceoryx2::service::service_name::ServiceNameError;
use mcm_shared::sample::{CommandSample, ReplyEntries, StateSample, open_reply_entries};
use mcm_shared::service::{STATE_KEY, ServiceNames};

/// The open ports of the bridge thread.
pub(super) struct Ports {
    _node: Node<ipc::Service>,
    pub(super) state: EntryHandle<ipc::Service, u32, StateSample>,
    /// The reply blocks, by key - 1.
    pub(super) reply_blocks: ReplyEntries,
    pub(super) publisher: Publisher<ipc::Service, CommandSample, ()>,
}

/// How a service of the core differs from what this gateway was built for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum LayoutMismatch {
    #[error("its key type is not `u32` ({0})")]
    StateKey(BlackboardOpenError),
    #[error("it has no `StateSample` entry of this gateway's type under key {STATE_KEY} ({0})")]
    StateEntry(EntryHandleError),
    #[error("it has no `ReplyBlock` entries of this gateway's type ({0})")]
    ReplyEntry(EntryHandleError),
    #[error("its payload type is not this gateway's `CommandSample` ({0})")]
    CommandPayload(PublishSubscribeOpenError),
}

/// Opening the core's services failed; one variant per step.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OpenError {
    #[error("`{name}` is not a valid iceoryx2 node name: {source:?}")]
    NodeName {
        name: String,
        source: SemanticStringError,
    },
    #[error("`{name}` is not a valid iceoryx2 service name: {source}")]
    ServiceName {
        name: String,
        source: ServiceNameError,
    },
    #[error("creating the gateway's iceoryx2 node failed: {0:?}")]
    Node(#[from] NodeCreationFailure),
    #[error("opening the state service `{service}` failed: {source}")]
    StateService {
        service: String,
        #[source]
        source: BlackboardOpenError,
    },
    #[error("creating a reader of the state service failed: {0}")]
    Reader(#[from] ReaderCreateError),
    #[error("opening the command service `{service}` failed: {source}")]
    CommandService {
        service: String,
        #[source]
        source: PublishSubscribeOpenError,
    },
    #[error("creating a publisher on the command service failed: {0}")]
    Publisher(#[from] PublisherCreateError),
    #[error(
        "the gateway was built with a different sample layout than mcm-rt: service `{service}`: \
         {source}; rebuild both from the same version"
    )]
    IncompatibleLayout {
        service: String,
        #[source]
        source: LayoutMismatch,
    },
}

impl OpenError {
    /// The core's services do not exist (yet): the core is not running.
    pub fn is_not_running(&self) -> bool {
        matches!(
            self,
            OpenError::StateService {
                source: BlackboardOpenError::DoesNotExist,
                ..
            } | OpenError::CommandService {
                source: PublishSubscribeOpenError::DoesNotExist,
                ..
            }
        )
    }
}

fn service_name(name: &str) -> Result<ServiceName, OpenError> {
    ServiceName::new(name).map_err(|source| OpenError::ServiceName {
        name: name.to_string(),
        source,
    })
}

fn node_name(name: &str) -> Result<NodeName, OpenError> {
    NodeName::new(name).map_err(|source| OpenError::NodeName {
        name: name.to_string(),
        source,
    })
}

/// Open the core's services of the instance `names`.
pub(super) fn open_ports(names: &ServiceNames) -> Result<Ports, OpenError> {
    let node = NodeBuilder::new()
        .name(&node_name(&names.node("mcm-gateway"))?)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()?;
    let service = names.state();
    let state_service = node
        .service_builder(&service_name(&service)?)
        .blackboard_opener::<u32>()
        .open()
        .map_err(|source| match source {
            BlackboardOpenError::IncompatibleKeys => OpenError::IncompatibleLayout {
                service: service.clone(),
                source: LayoutMismatch::StateKey(source),
            },
            source => OpenError::StateService {
                service: service.clone(),
                source,
            },
        })?;
    let reader = state_service.reader_builder().create()?;
    // The core adds its entry when it creates the service, so a missing entry is one of
    // another type (a `StateSample` of another layout).
    let state =
        reader
            .entry::<StateSample>(&STATE_KEY)
            .map_err(|e| OpenError::IncompatibleLayout {
                service: service.clone(),
                source: LayoutMismatch::StateEntry(e),
            })?;
    let reply_blocks = open_reply_entries(&reader).map_err(|e| OpenError::IncompatibleLayout {
        service: service.clone(),
        source: LayoutMismatch::ReplyEntry(e.source),
    })?;
    let service = names.command();
    let command_service = node
        .service_builder(&service_name(&service)?)
        .publish_subscribe::<CommandSample>()
        .open()
        .map_err(|source| match source {
            PublishSubscribeOpenError::IncompatibleTypes => OpenError::IncompatibleLayout {
                service: service.clone(),
                source: LayoutMismatch::CommandPayload(source),
            },
            source => OpenError::CommandService {
                service: service.clone(),
                source,
            },
        })?;
    let publisher = command_service.publisher_builder().create()?;
    Ok(Ports {
        _node: node,
        state,
        reply_blocks,
        publisher,
    })
}
