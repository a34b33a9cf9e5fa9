//! Who is who: the registry of this gateway's connections (client id -> channel and peer
//! address), so that a refusal can name the client that controls the arm in words, and the
//! identity one connection carries ([`Client`]): its id, its peer, whether it presented the
//! shared secret. When a connection ends, its [`Client`] tells the real-time core that the
//! client is gone (`Request::ClientGone`), which ends its control and stops what it drove.

use crate::core_link::bridge::Bridge;
use std::collections::HashMap;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

/// The network channels of the gateway.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    Json,
    Hmi,
    /// A peer (routing id) of the ZeroMQ ROUTER socket.
    Zmq,
    /// A browser page of the pendant (its WebSocket).
    Web,
}

impl Channel {
    /// The channel in words, e.g. "JSON client".
    pub fn words(self) -> &'static str {
        match self {
            Channel::Json => "JSON client",
            Channel::Hmi => "HMI client",
            Channel::Zmq => "ZeroMQ client",
            Channel::Web => "browser pendant",
        }
    }
}

/// This gateway's connections by client id; cheap to clone.
#[derive(Debug, Clone, Default)]
pub struct Clients(Arc<Mutex<HashMap<u64, (Channel, SocketAddr)>>>);

impl Clients {
    fn map(&self) -> std::sync::MutexGuard<'_, HashMap<u64, (Channel, SocketAddr)>> {
        // The map holds plain data: a panic elsewhere cannot leave it half-changed.
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    pub fn insert(&self, id: u64, channel: Channel, peer: SocketAddr) {
        self.map().insert(id, (channel, peer));
    }

    pub fn remove(&self, id: u64) {
        self.map().remove(&id);
    }

    /// Every connection known now: id, channel and peer, by id.
    pub fn list(&self) -> Vec<(u64, Channel, SocketAddr)> {
        let mut all: Vec<_> = self
            .map()
            .iter()
            .map(|(id, (c, p))| (*id, *c, *p))
            .collect();
        all.sort_by_key(|(id, _, _)| *id);
        all
    }

    /// The client `id` in words: "JSON client 10.1.2.3:51234", "HMI client 127.0.0.1:40000",
    /// or, for an id that is not a connection of this gateway, "shared-memory client 0x..."
    /// with the program whose process made it, e.g. "... of mcm-ros2 (pid 4242)".
    pub fn who(&self, id: u64) -> String {
        if id == 0 {
            return "nobody".to_string();
        }
        match self.map().get(&id) {
            Some((channel, peer)) => format!("{} {peer}", channel.words()),
            None => match mcm_client::shm::client_process(id) {
                Some((pid, program)) if program != "mcm-gateway" => {
                    format!("shared-memory client {id:#x} of {program} (pid {pid})")
                }
                _ => format!(
                    "shared-memory client {id:#x} (not a connection of this gateway; it may also \
                     be a connection of a gateway that has since restarted)"
                ),
            },
        }
    }
}

/// The identity of one connection; cheap to clone. When the last clone is dropped (the
/// connection ended, however) it leaves the registry and, when it may control the arm, tells
/// the core it is gone.
#[derive(Clone)]
pub struct Client(Arc<Identity>);

/// What [`Client`] holds.
pub struct Identity {
    pub id: u64,
    pub peer: SocketAddr,
    /// The connection presented the right shared secret.
    authenticated: AtomicBool,
    /// The connection sent a command that may have given it control.
    might_own: AtomicBool,
    clients: Clients,
    bridge: Bridge,
}

impl Client {
    /// A new connection from `peer`, registered under a fresh client id.
    pub fn new(clients: &Clients, bridge: &Bridge, channel: Channel, peer: SocketAddr) -> Client {
        let id = bridge.new_client_id();
        clients.insert(id, channel, peer);
        Client(Arc::new(Identity {
            id,
            peer,
            authenticated: AtomicBool::new(false),
            might_own: AtomicBool::new(false),
            clients: clients.clone(),
            bridge: bridge.clone(),
        }))
    }
}

impl std::ops::Deref for Client {
    type Target = Identity;
    fn deref(&self) -> &Identity {
        &self.0
    }
}

impl Identity {
    pub fn authenticated(&self) -> bool {
        self.authenticated.load(Ordering::Relaxed)
    }

    pub fn set_authenticated(&self) {
        self.authenticated.store(true, Ordering::Relaxed);
    }

    /// Remember that this connection may control the arm (it sent a motion command).
    pub fn may_own(&self) {
        self.might_own.store(true, Ordering::Relaxed);
    }
}

impl Drop for Identity {
    fn drop(&mut self) {
        let (id, clients) = (self.id, self.clients.clone());
        // Ahead of other clients' work, like `hold`: the core ends this client's control (and
        // stops what it drove) in the next cycle.
        self.bridge.client_gone(id);
        match tokio::runtime::Handle::try_current() {
            Ok(h) if self.might_own.load(Ordering::Relaxed) => {
                let mut state = self.bridge.watch_state();
                h.spawn(async move {
                    // Kept until the core no longer names it as the owner, so that refusals
                    // name it in words until then.
                    let released =
                        state.wait_for(|s| s.as_ref().is_none_or(|s| s.owner_client_id != id));
                    let _ = tokio::time::timeout(crate::command::REPLY_TIMEOUT, released).await;
                    clients.remove(id);
                });
            }
            _ => clients.remove(id),
        }
    }
}
