//! Which connections a port admits, and which one it closes to make room: the per-peer cap,
//! the total cap with its loopback reserve, and eviction of the longest-idle connection, never
//! one that is busy or that controls the arm (rules in docs/protocol.md, "Connections", and
//! docs/security.md). Runs in the gateway's async tasks; the table
//! is locked only for a few map operations, never across an `.await`.

use mcm_shared::config::ConnectionLimits;
use std::collections::BTreeMap;
use std::net::IpAddr;
use std::sync::{Arc, Mutex, MutexGuard};
use tokio::sync::watch;
use tokio::time::Instant;

/// The address a per-peer cap counts: the IP address itself, except that all IPv6 addresses
/// of one /64 network (what one host or site usually gets) count as one peer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PeerKey(IpAddr);

impl PeerKey {
    pub fn of(ip: IpAddr) -> Self {
        match ip.to_canonical() {
            IpAddr::V6(v6) if !v6.is_loopback() => {
                let bits = u128::from(v6) & !((1u128 << 64) - 1);
                Self(IpAddr::V6(bits.into()))
            }
            other => Self(other),
        }
    }
}

impl std::fmt::Display for PeerKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0 {
            IpAddr::V6(v6) if !v6.is_loopback() => write!(f, "{v6}/64"),
            ip => write!(f, "{ip}"),
        }
    }
}

/// One admitted connection.
#[derive(Debug)]
struct Entry {
    peer: PeerKey,
    local: bool,
    /// Since when the connection has sent no complete line (or finished its last command).
    idle_since: Instant,
    /// A command executed by the core is running, or a torque session: never evicted.
    busy: bool,
    /// The connection's client id ([`Slot::identify`]; 0 until known): the one that controls
    /// the arm is never evicted.
    client: u64,
    /// Receives the reason when the connection is evicted.
    evict: watch::Sender<Option<String>>,
}

/// Which connection could make room.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Victim {
    Found(u64),
    /// None but the one that controls the arm.
    OnlyOwner,
    None,
}

/// A connection the table admitted.
#[derive(Debug)]
pub struct Admitted {
    pub id: u64,
    /// Where the connection hears that it was evicted (for its [`Slot`]).
    pub evict: watch::Receiver<Option<String>>,
}

/// The connections of one port.
#[derive(Debug)]
pub struct Table {
    limits: ConnectionLimits,
    entries: BTreeMap<u64, Entry>,
    next_id: u64,
}

/// Whole seconds (or tenths below ten) for messages.
pub fn secs(s: f64) -> String {
    if s < 10.0 {
        format!("{s:.1}")
    } else {
        format!("{s:.0}")
    }
}

/// `ip` is the same host as a loopback peer (`::ffff:127.0.0.1` included).
pub fn is_loopback(ip: IpAddr) -> bool {
    ip.to_canonical().is_loopback()
}

impl Table {
    pub fn new(limits: ConnectionLimits) -> Self {
        Self {
            limits,
            entries: BTreeMap::new(),
            next_id: 1,
        }
    }

    /// Connections held now.
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    #[cfg(test)]
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The ids of the connections held now.
    #[cfg(test)]
    pub(crate) fn ids(&self) -> Vec<u64> {
        self.entries.keys().copied().collect()
    }

    /// The longest-idle connection among those `eligible` that is neither busy nor the one
    /// whose client id is `owner` (it controls the arm; 0: nobody does), oldest id first on a
    /// tie.
    fn longest_idle(&self, owner: u64, eligible: impl Fn(&Entry) -> bool) -> Victim {
        let mut owner_idle = false;
        let found = self
            .entries
            .iter()
            .filter(|(_, e)| !e.busy && eligible(e))
            .filter(|(_, e)| {
                let owns = owner != 0 && e.client == owner;
                owner_idle |= owns;
                !owns
            })
            .min_by_key(|(id, e)| (e.idle_since, **id))
            .map(|(id, _)| *id);
        match found {
            Some(id) => Victim::Found(id),
            None if owner_idle => Victim::OnlyOwner,
            None => Victim::None,
        }
    }

    /// Admit a connection from `ip` (`local`: a loopback peer) at `now`, while the client
    /// `owner` controls the arm (0: nobody). When a cap is reached, the longest-idle connection
    /// that the newcomer may displace is closed with a reason (sent to its [`Slot`], which
    /// ends it); if there is none, the newcomer is refused with the reason (`Err`). A remote
    /// peer never displaces a loopback connection; a busy connection and the one that controls
    /// the arm are never displaced.
    pub fn admit(
        &mut self,
        ip: IpAddr,
        local: bool,
        now: Instant,
        owner: u64,
    ) -> Result<Admitted, String> {
        let l = &self.limits;
        let (max, per_peer, reserve) = (l.max_connections, l.max_per_peer, l.loopback_reserve);
        let peer = PeerKey::of(ip);
        let same_peer = self.entries.values().filter(|e| e.peer == peer).count();
        let remote = self.entries.values().filter(|e| !e.local).count();
        let total = self.entries.len();
        let (victim, why) = if same_peer >= per_peer {
            (
                self.longest_idle(owner, |e| e.peer == peer),
                format!(
                    "{peer} already has {same_peer} connections (at most {per_peer} per address)"
                ),
            )
        } else if local && total >= max {
            (
                self.longest_idle(owner, |_| true),
                format!("all {max} connections of this port are in use"),
            )
        } else if !local && (total >= max || remote >= max - reserve) {
            (
                self.longest_idle(owner, |e| !e.local),
                format!(
                    "all {} connections open to remote peers are in use ({reserve} of {max} are kept for loopback)",
                    max - reserve
                ),
            )
        } else {
            (Victim::None, String::new())
        };
        match (why.is_empty(), victim) {
            (true, _) => {}
            (false, Victim::None) => {
                return Err(format!(
                    "connection refused: {why} and none of them is idle; try again later"
                ));
            }
            (false, Victim::OnlyOwner) => {
                return Err(format!(
                    "connection refused: {why}; the only idle one controls the arm, and the \
                     connection that controls the arm is never closed to make room; try again \
                     later, or have it send `release_control` or disconnect"
                ));
            }
            (false, Victim::Found(id)) => {
                let e = self.entries.remove(&id).expect("victim is in the table");
                let idle = now.saturating_duration_since(e.idle_since).as_secs_f64();
                let reason = format!(
                    "connection closed to make room for a new one: {why} and this one was the longest idle ({} s without a command)",
                    secs(idle)
                );
                let _ = e.evict.send(Some(reason));
            }
        }
        let id = self.next_id;
        self.next_id += 1;
        let (evict, rx) = watch::channel(None);
        self.entries.insert(
            id,
            Entry {
                peer,
                local,
                idle_since: now,
                busy: false,
                client: 0,
                evict,
            },
        );
        Ok(Admitted { id, evict: rx })
    }

    /// Connection `id` is busy or not, and active at `now`.
    pub(crate) fn update(&mut self, id: u64, busy: bool, now: Instant) {
        if let Some(e) = self.entries.get_mut(&id) {
            e.busy = busy;
            e.idle_since = now;
        }
    }

    /// Connection `id` is the client `client`.
    fn identify(&mut self, id: u64, client: u64) {
        if let Some(e) = self.entries.get_mut(&id) {
            e.client = client;
        }
    }

    fn remove(&mut self, id: u64) {
        self.entries.remove(&id);
    }
}

/// A port's table, shared by its accept loop and its connections.
#[derive(Debug, Clone)]
pub struct Shared(Arc<Mutex<Table>>);

impl Shared {
    pub fn new(limits: ConnectionLimits) -> Self {
        Self(Arc::new(Mutex::new(Table::new(limits))))
    }

    /// The table; a panic while it was held cannot leave it inconsistent (every update is a
    /// single map operation), so a poisoned lock is taken as is.
    pub fn lock(&self) -> MutexGuard<'_, Table> {
        self.0.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// A connection's place in its port's table: tells the table when the connection is busy or
/// active, and delivers the eviction reason. Dropping it frees the place.
#[derive(Debug)]
pub struct Slot {
    id: u64,
    table: Shared,
    evict: watch::Receiver<Option<String>>,
    idle_since: Instant,
}

impl Slot {
    pub fn new(id: u64, table: Shared, evict: watch::Receiver<Option<String>>) -> Self {
        Self {
            id,
            table,
            evict,
            idle_since: Instant::now(),
        }
    }

    /// Since when the connection has been idle.
    pub fn idle_since(&self) -> Instant {
        self.idle_since
    }

    /// The connection is the client `client` (its [`crate::command::access::Client`] id): while
    /// that client controls the arm, the connection is not closed to make room.
    pub fn identify(&mut self, client: u64) {
        self.table.lock().identify(self.id, client);
    }

    /// A complete line arrived: the connection is active now.
    pub fn touch(&mut self) {
        self.set_busy(false);
    }

    /// Busy (a command executed by the core runs, a torque session: never evicted) or not;
    /// either way active now.
    pub fn set_busy(&mut self, busy: bool) {
        self.idle_since = Instant::now();
        self.table.lock().update(self.id, busy, self.idle_since);
    }

    /// Resolves with the reason once the connection was evicted; never otherwise.
    pub async fn evicted(&mut self) -> String {
        let reason = match self.evict.wait_for(Option::is_some).await {
            Ok(reason) => reason.clone(),
            Err(_) => None,
        };
        match reason {
            Some(r) => r,
            None => std::future::pending().await,
        }
    }
}

impl Drop for Slot {
    fn drop(&mut self) {
        self.table.lock().remove(self.id);
    }
}

#[cfg(test)]
mod tests;
