//! The ports every client of the real-time core holds on the core's services: the state
//! blackboard (the state and the reply blocks, read), the command service (publish) and the
//! state event (listen). Both clients of the core use this one layer: [`ShmClient`] of this
//! crate, and the gateway's bridge thread, which is a client of the core like any co-located
//! controller.
//!
//! Why here and not in `mcm-shared`: `mcm-shared` is the contract, what the core and its peers
//! must agree on (the sample layouts, the service names and their QoS, the encodings). How a
//! peer opens those services, checks their versions, numbers its requests and finds its replies
//! is the client side's behaviour, not part of the agreement; the core never uses it. So the
//! layer lives in the client library, and the gateway depends on `mcm-client` for it.
//!
//! - [`CorePorts::open`] opens the state blackboard and the command service with the versions
//!   checked ([`OpenError::Incompatible`] names the service, what differs and the type this
//!   build expects); a core that is not running is [`OpenError::NotRunning`].
//! - [`open_state_event`] opens a listener of the state event, on a node of its own or the
//!   ports' ([`CorePorts::open_state_event`]).
//! - [`CorePorts::publish`] stamps a request with its client and request id and publishes it.
//! - [`CorePorts::replies`] reads the replies the core numbered since the last read
//!   ([`super::replies`]).
//!
//! Every error keeps iceoryx2's own error as its source.
//!
//! [`ShmClient`]: super::ShmClient

mod error;
mod open;

#[cfg(test)]
mod tests;

pub use error::{LayoutMismatch, OpenError, SendError, ServiceOpenError};
pub use open::{describe, open_node, open_state_event};

use super::replies::Replies;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::reader::EntryHandle;
use iceoryx2::prelude::*;
use mcm_shared::command::Request;
use mcm_shared::sample::{CommandSample, StateSample};
use mcm_shared::service::ServiceNames;
use std::fmt;

/// Who opens the core's services: names its iceoryx2 node and its version errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Peer {
    /// A program using this library ([`super::ShmClient`]).
    Client,
    /// The gateway's bridge thread.
    Gateway,
}

impl Peer {
    /// The role in the node name (`<role>.<instance>`).
    pub fn role(self) -> &'static str {
        match self {
            Peer::Client => "mcm-client",
            Peer::Gateway => "mcm-gateway",
        }
    }
}

impl fmt::Display for Peer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Peer::Client => "client",
            Peer::Gateway => "gateway",
        })
    }
}

/// The open ports of one client of the core. Not `Send` (iceoryx2's ports are bound to their
/// thread).
pub struct CorePorts {
    state: EntryHandle<ipc::Service, u32, StateSample>,
    replies: Replies,
    publisher: Publisher<ipc::Service, CommandSample, ()>,
    names: ServiceNames,
    // Dropped last: the ports above were made through it.
    node: Node<ipc::Service>,
}

impl CorePorts {
    /// Open the state blackboard and the command service of the instance `names` as `peer`.
    pub fn open(names: &ServiceNames, peer: Peer) -> Result<CorePorts, OpenError> {
        let node = open_node(names, peer.role())?;
        let (state, replies) = open::state(&node, names, peer)?;
        let publisher = open::publisher(&node, names, peer)?;
        Ok(CorePorts {
            state,
            replies: Replies::new(replies),
            publisher,
            names: names.clone(),
            node,
        })
    }

    /// A listener of the core's state event, through these ports' node.
    pub fn open_state_event(&self) -> Result<Listener<ipc::Service>, OpenError> {
        open_state_event(&self.node, &self.names)
    }

    /// The instance's service names.
    pub fn names(&self) -> &ServiceNames {
        &self.names
    }

    /// The newest state.
    pub fn state(&self) -> StateSample {
        *self.state.get()
    }

    /// The reply blocks, and how far they were read.
    pub fn replies(&mut self) -> &mut Replies {
        &mut self.replies
    }

    /// Publish `req` stamped with `client_id` and `request_id` (the ids its reply carries).
    pub fn publish(&self, req: &Request, client_id: u64, request_id: u64) -> Result<(), SendError> {
        let mut sample = req.encode();
        sample.client_id = client_id;
        sample.request_id = request_id;
        self.publisher
            .send_copy(sample)
            .map(|_| ())
            .map_err(|source| SendError {
                command: req.kind(),
                service: self.names.command(),
                source,
            })
    }
}
