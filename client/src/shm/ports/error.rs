//! What opening the core's services and publishing on them can end with; each keeps iceoryx2's
//! own error as its source.

use super::Peer;
use iceoryx2::node::NodeCreationFailure;
use iceoryx2::port::listener::ListenerCreateError;
use iceoryx2::port::publisher::PublisherCreateError;
use iceoryx2::port::reader::{EntryHandleError, ReaderCreateError};
use iceoryx2::prelude::SemanticStringError;
use iceoryx2::service::builder::blackboard::BlackboardOpenError;
use iceoryx2::service::builder::event::EventOpenError;
use iceoryx2::service::builder::publish_subscribe::PublishSubscribeOpenError;
use mcm_shared::mode::CommandKind;
use mcm_shared::sample::REPLY_BLOCKS;
use mcm_shared::service::{COMMAND_MAX_PUBLISHERS, InvalidInstanceName};

/// iceoryx2's error opening one of the core's services.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum ServiceOpenError {
    #[error(transparent)]
    Blackboard(#[from] BlackboardOpenError),
    #[error(transparent)]
    PublishSubscribe(#[from] PublishSubscribeOpenError),
    #[error(transparent)]
    Event(#[from] EventOpenError),
}

impl ServiceOpenError {
    /// The service does not exist.
    pub fn does_not_exist(&self) -> bool {
        matches!(
            self,
            ServiceOpenError::Blackboard(BlackboardOpenError::DoesNotExist)
                | ServiceOpenError::PublishSubscribe(PublishSubscribeOpenError::DoesNotExist)
                | ServiceOpenError::Event(EventOpenError::DoesNotExist)
        )
    }
}

/// Opening the core's services failed; one variant per step.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OpenError {
    #[error(transparent)]
    InstanceName(#[from] InvalidInstanceName),
    #[error("iceoryx2 refuses the node name `{name}`: {source}")]
    NodeName {
        name: String,
        #[source]
        source: SemanticStringError,
    },
    #[error("creating the iceoryx2 node `{name}` failed: {source}")]
    Node {
        name: String,
        #[source]
        source: NodeCreationFailure,
    },
    /// The MCM of this instance is not running (its service does not exist).
    #[error(
        "the MCM instance {instance:?} is not running on this computer (service `{service}` does not exist); start it (`cargo run --release -- --instance {instance}`) or check the instance name"
    )]
    NotRunning {
        instance: String,
        service: String,
        #[source]
        source: ServiceOpenError,
    },
    /// Opening a service failed for another reason than its absence or its layout.
    #[error("opening `{service}` failed: {source}")]
    Service {
        service: String,
        #[source]
        source: ServiceOpenError,
    },
    /// The core's service is of another MCM version than this build.
    #[error(
        "service `{service}` of the running MCM does not match this {peer}: {mismatch}; build the {peer} from the same MCM version as the running core (iceoryx2 =0.10.0, {expected})"
    )]
    Incompatible {
        service: String,
        peer: Peer,
        #[source]
        mismatch: LayoutMismatch,
        /// The sample type this build expects (type name, size, alignment).
        expected: String,
    },
    #[error("creating a reader of `{service}` failed: {source}")]
    Reader {
        service: String,
        #[source]
        source: ReaderCreateError,
    },
    #[error(
        "creating a publisher on `{service}` failed (at most {COMMAND_MAX_PUBLISHERS} publishers: the gateway and up to {} controllers): {source}",
        COMMAND_MAX_PUBLISHERS - 1
    )]
    Publisher {
        service: String,
        #[source]
        source: PublisherCreateError,
    },
    #[error("creating a listener of `{service}` failed: {source}")]
    Listener {
        service: String,
        #[source]
        source: ListenerCreateError,
    },
}

impl OpenError {
    /// The core's services do not exist (yet): the core is not running.
    pub fn is_not_running(&self) -> bool {
        matches!(self, OpenError::NotRunning { .. })
    }
}

/// Which entry of the state blackboard.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Entry {
    State,
    ReplyBlock,
}

/// How a service of the core differs from what this build expects.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LayoutMismatch {
    #[error("its key type is not u32")]
    StateKey(#[source] BlackboardOpenError),
    /// The entry `key` is of another type, or missing (`keys`: how many the blackboard has).
    #[error(
        "{}",
        if *present {
            format!("its {} (key {key}) is of another type, size or alignment", entry.words())
        } else {
            format!(
                "it has no {} (key {key}); it has {keys} keys, {} expected",
                entry.words(),
                REPLY_BLOCKS + 1
            )
        }
    )]
    Entry {
        entry: Entry,
        key: u32,
        present: bool,
        keys: usize,
        #[source]
        source: EntryHandleError,
    },
    /// The command service carries another payload (`found`: the core's, in words, when
    /// iceoryx2 tells it).
    #[error(
        "{}",
        match found {
            Some(found) => format!("its payload is {found}"),
            None => "its payload type is another".to_string(),
        }
    )]
    CommandPayload {
        found: Option<String>,
        #[source]
        source: PublishSubscribeOpenError,
    },
}

impl Entry {
    fn words(self) -> &'static str {
        match self {
            Entry::State => "state entry",
            Entry::ReplyBlock => "reply block",
        }
    }
}

/// Publishing a command on the core's command service failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("publishing {command} on `{service}` failed: {source}")]
pub struct SendError {
    pub command: CommandKind,
    pub service: String,
    #[source]
    pub source: iceoryx2::port::SendError,
}
