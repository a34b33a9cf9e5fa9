//! Which connections a port admits, and which one it closes to make room: the per-peer cap,
//! the total cap with its loopback reserve, and eviction of the longest-idle connection
//! (rules in docs/protocol.md, "Connections"). Runs in the gateway's async tasks; the table
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
    /// Receives the reason when the connection is evicted.
    evict: watch::Sender<Option<String>>,
}

/// A connection the table closed to make room for a new one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Evicted {
    pub id: u64,
    pub reason: String,
}

/// A connection the table admitted.
#[derive(Debug)]
pub struct Admitted {
    pub id: u64,
    /// Where the connection hears that it was evicted (for its [`Slot`]).
    pub evict: watch::Receiver<Option<String>>,
    /// The connection closed to make room, if any.
    pub evicted: Option<Evicted>,
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
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The ids of the connections held now.
    #[cfg(test)]
    pub(crate) fn ids(&self) -> Vec<u64> {
        self.entries.keys().copied().collect()
    }

    /// Connections that are busy now (a command in the core, a torque session).
    pub fn busy(&self) -> usize {
        self.entries.values().filter(|e| e.busy).count()
    }

    /// The longest-idle connection that is not busy among those `eligible`, oldest id first
    /// on a tie.
    fn longest_idle(&self, eligible: impl Fn(&Entry) -> bool) -> Option<u64> {
        self.entries
            .iter()
            .filter(|(_, e)| !e.busy && eligible(e))
            .min_by_key(|(id, e)| (e.idle_since, **id))
            .map(|(id, _)| *id)
    }

    /// Admit a connection from `ip` (`local`: a loopback peer) at `now`. When a cap is
    /// reached, the longest-idle connection that the newcomer may displace is closed with a
    /// reason (sent to its [`Slot`]) and returned; if there is none, the newcomer is refused
    /// with the reason (`Err`). A remote peer never displaces a loopback connection.
    pub fn admit(&mut self, ip: IpAddr, local: bool, now: Instant) -> Result<Admitted, String> {
        let l = &self.limits;
        let (max, per_peer, reserve) = (l.max_connections, l.max_per_peer, l.loopback_reserve);
        let peer = PeerKey::of(ip);
        let same_peer = self.entries.values().filter(|e| e.peer == peer).count();
        let remote = self.entries.values().filter(|e| !e.local).count();
        let total = self.entries.len();
        let (victim, why) = if same_peer >= per_peer {
            (
                self.longest_idle(|e| e.peer == peer),
                format!(
                    "{peer} already has {same_peer} connections (at most {per_peer} per address)"
                ),
            )
        } else if local && total >= max {
            (
                self.longest_idle(|_| true),
                format!("all {max} connections of this port are in use"),
            )
        } else if !local && (total >= max || remote >= max - reserve) {
            (
                self.longest_idle(|e| !e.local),
                format!(
                    "all {} connections open to remote peers are in use ({reserve} of {max} are kept for loopback)",
                    max - reserve
                ),
            )
        } else {
            (None, String::new())
        };
        let evicted = match (why.is_empty(), victim) {
            (true, _) => None,
            (false, None) => {
                return Err(format!(
                    "connection refused: {why} and none of them is idle; try again later"
                ));
            }
            (false, Some(id)) => {
                let e = self.entries.remove(&id).expect("victim is in the table");
                let idle = now.saturating_duration_since(e.idle_since).as_secs_f64();
                let reason = format!(
                    "connection closed to make room for a new one: {why} and this one was the longest idle ({} s without a command)",
                    secs(idle)
                );
                let _ = e.evict.send(Some(reason.clone()));
                Some(Evicted { id, reason })
            }
        };
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
                evict,
            },
        );
        Ok(Admitted {
            id,
            evict: rx,
            evicted,
        })
    }

    /// Connection `id` is busy or not, and active at `now`.
    pub(crate) fn update(&mut self, id: u64, busy: bool, now: Instant) {
        if let Some(e) = self.entries.get_mut(&id) {
            e.busy = busy;
            e.idle_since = now;
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
mod tests {
    use super::*;
    use std::time::Duration;

    fn limits(max: usize, per_peer: usize, reserve: usize) -> ConnectionLimits {
        ConnectionLimits {
            max_connections: max,
            max_per_peer: per_peer,
            loopback_reserve: reserve,
            ..ConnectionLimits::default()
        }
    }

    fn ip(s: &str) -> IpAddr {
        s.parse().unwrap()
    }

    /// Admit `peer` at `t0 + at` seconds; returns (id, evicted id).
    fn admit(t: &mut Table, peer: &str, at: u64) -> Result<(u64, Option<u64>), String> {
        let t0 = Instant::now();
        let p = ip(peer);
        let a = t.admit(p, is_loopback(p), t0 + Duration::from_secs(at))?;
        Ok((a.id, a.evicted.map(|e| e.id)))
    }

    #[test]
    fn the_per_peer_cap_closes_the_longest_idle_of_that_peer() {
        let mut t = Table::new(limits(10, 2, 0));
        let (a, _) = admit(&mut t, "10.0.0.1", 0).unwrap();
        let (b, _) = admit(&mut t, "10.0.0.1", 1).unwrap();
        admit(&mut t, "10.0.0.2", 0).unwrap();
        t.update(a, false, Instant::now() + Duration::from_secs(5));
        // `a` was active later than `b`: `b` is the longest idle of 10.0.0.1.
        assert_eq!(admit(&mut t, "10.0.0.1", 6).unwrap().1, Some(b));
        assert_eq!(t.len(), 3);
    }

    #[test]
    fn busy_connections_are_never_evicted_and_the_newcomer_is_refused() {
        let mut t = Table::new(limits(10, 1, 0));
        let (a, _) = admit(&mut t, "10.0.0.1", 0).unwrap();
        t.update(a, true, Instant::now());
        let e = admit(&mut t, "10.0.0.1", 1).unwrap_err();
        assert!(
            e.contains("10.0.0.1 already has 1 connections (at most 1 per address)"),
            "{e}"
        );
        assert!(e.contains("none of them is idle"), "{e}");
    }

    #[test]
    fn the_reserve_keeps_slots_for_loopback_and_remote_never_displaces_loopback() {
        let mut t = Table::new(limits(4, 4, 2));
        admit(&mut t, "10.0.0.1", 0).unwrap();
        admit(&mut t, "10.0.0.2", 1).unwrap();
        // Remote peers hold their 2 slots: a third remote peer displaces the longest idle one.
        let (c, ev) = admit(&mut t, "10.0.0.3", 2).unwrap();
        assert!(ev.is_some());
        // Loopback still gets the two reserved slots.
        admit(&mut t, "127.0.0.1", 3).unwrap();
        admit(&mut t, "::1", 4).unwrap();
        assert_eq!(t.len(), 4);
        // A remote newcomer displaces a remote connection, never a loopback one.
        let (_, ev) = admit(&mut t, "10.0.0.4", 5).unwrap();
        assert!(
            ev.is_some_and(|id| id != c),
            "the longest-idle remote one (10.0.0.2)"
        );
        assert_eq!(t.entries.values().filter(|e| e.local).count(), 2);
        // With every remote connection busy, a remote newcomer is refused ...
        let remote: Vec<u64> = t
            .entries
            .iter()
            .filter(|(_, e)| !e.local)
            .map(|(i, _)| *i)
            .collect();
        for id in remote {
            t.update(id, true, Instant::now());
        }
        let e = admit(&mut t, "10.0.0.5", 6).unwrap_err();
        assert!(e.contains("2 of 4 are kept for loopback"), "{e}");
        // ... while loopback displaces its own longest-idle connection.
        let (_, ev) = admit(&mut t, "127.0.0.1", 7).unwrap();
        assert!(ev.is_some());
        assert_eq!(t.len(), 4);
    }

    #[test]
    fn the_evicted_slot_hears_its_reason_and_a_dropped_slot_frees_its_place() {
        let shared = Shared::new(limits(1, 1, 0));
        let t0 = Instant::now();
        let first = shared.lock().admit(ip("127.0.0.1"), true, t0).unwrap();
        let id = first.id;
        let mut slot = Slot::new(id, shared.clone(), first.evict);
        let second = shared
            .lock()
            .admit(ip("127.0.0.1"), true, t0 + Duration::from_secs(42))
            .unwrap();
        let ev = second.evicted.expect("the first one is evicted");
        assert_eq!(ev.id, id);
        assert!(
            ev.reason.contains("longest idle (42 s without a command)"),
            "{}",
            ev.reason
        );
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_time()
            .build()
            .unwrap();
        assert_eq!(rt.block_on(slot.evicted()), ev.reason);
        drop(slot);
        assert_eq!(
            shared.lock().len(),
            1,
            "dropping the evicted slot frees nothing more"
        );
        drop(Slot::new(second.id, shared.clone(), second.evict));
        assert!(shared.lock().is_empty());
    }

    #[test]
    fn one_ipv6_network_is_one_peer() {
        let mut t = Table::new(limits(10, 1, 0));
        admit(&mut t, "2001:db8:1:2::10", 0).unwrap();
        let (_, ev) = admit(&mut t, "2001:db8:1:2:ffff::1", 1).unwrap();
        assert!(ev.is_some(), "same /64: the per-peer cap applies");
        let (_, ev) = admit(&mut t, "2001:db8:1:3::10", 2).unwrap();
        assert!(ev.is_none(), "another /64 is another peer");
        assert_eq!(
            PeerKey::of(ip("2001:db8:1:2::10")).to_string(),
            "2001:db8:1:2::/64"
        );
        assert_eq!(PeerKey::of(ip("::ffff:10.0.0.1")).to_string(), "10.0.0.1");
    }

    #[test]
    fn mapped_loopback_counts_as_loopback() {
        assert!(is_loopback(ip("::ffff:127.0.0.1")));
        assert!(is_loopback(ip("127.0.0.2")));
        assert!(!is_loopback(ip("10.0.0.1")));
    }
}
