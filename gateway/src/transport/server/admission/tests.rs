//! The admission table's rules, on a table alone (no sockets): caps, reserve, who is
//! evicted and who never is.

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

/// Admit `peer` at `t0 + at` seconds while nobody controls the arm; returns (id, evicted id).
fn admit(t: &mut Table, peer: &str, at: u64) -> Result<(u64, Option<u64>), String> {
    admit_owned(t, peer, at, 0)
}

/// [`admit`] while the client `owner` controls the arm.
fn admit_owned(
    t: &mut Table,
    peer: &str,
    at: u64,
    owner: u64,
) -> Result<(u64, Option<u64>), String> {
    let t0 = Instant::now();
    let p = ip(peer);
    let before = t.ids();
    let a = t.admit(p, is_loopback(p), t0 + Duration::from_secs(at), owner)?;
    let after = t.ids();
    let gone: Vec<u64> = before
        .into_iter()
        .filter(|id| !after.contains(id))
        .collect();
    assert!(
        gone.len() <= 1,
        "one connection makes room at most: {gone:?}"
    );
    Ok((a.id, gone.first().copied()))
}

#[test]
fn the_connection_that_controls_the_arm_is_never_evicted() {
    let mut t = Table::new(limits(10, 3, 0));
    let (owner, _) = admit(&mut t, "10.0.0.1", 0).unwrap();
    t.identify(owner, 0x77);
    let (b, _) = admit(&mut t, "10.0.0.1", 1).unwrap();
    let (c, _) = admit(&mut t, "10.0.0.1", 2).unwrap();
    t.identify(b, 0x78);
    // The owner is the longest idle; the next longest idle of the others goes.
    assert_eq!(admit_owned(&mut t, "10.0.0.1", 3, 0x77).unwrap().1, Some(b));
    // With the others busy, the newcomer is refused: the owner alone could make room.
    for id in t.ids() {
        if id != owner {
            t.update(id, true, Instant::now());
        }
    }
    let e = admit_owned(&mut t, "10.0.0.1", 4, 0x77).unwrap_err();
    assert!(
        e.starts_with("connection refused: 10.0.0.1 already has 3 connections"),
        "{e}"
    );
    assert!(
        e.contains("the only idle one controls the arm, and the connection that controls the arm is never closed"),
        "{e}"
    );
    assert!(t.ids().contains(&owner) && t.ids().contains(&c));
    // Once it no longer controls the arm, it is an idle connection like any other.
    assert_eq!(
        admit_owned(&mut t, "10.0.0.1", 5, 0).unwrap().1,
        Some(owner)
    );
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
    let first = shared.lock().admit(ip("127.0.0.1"), true, t0, 0).unwrap();
    let id = first.id;
    let mut slot = Slot::new(id, shared.clone(), first.evict);
    let second = shared
        .lock()
        .admit(ip("127.0.0.1"), true, t0 + Duration::from_secs(42), 0)
        .unwrap();
    assert_eq!(shared.lock().ids(), [second.id], "the first one is evicted");
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_time()
        .build()
        .unwrap();
    let reason = rt.block_on(slot.evicted());
    assert!(
        reason.contains("longest idle (42 s without a command)"),
        "{reason}"
    );
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
