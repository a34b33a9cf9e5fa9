use super::*;
use proptest::prelude::*;

fn w(client_id: u64, urgent: bool) -> Waiting {
    Waiting { client_id, urgent }
}

fn pick(waiting: &[Waiting], cursor: u64, max: usize) -> (Vec<usize>, u64) {
    let mut scratch = Scratch::new(waiting.len().max(1));
    let mut picked = vec![0; max];
    let (n, cursor) = select(waiting, cursor, &mut scratch, &mut picked);
    picked.truncate(n);
    (picked, cursor)
}

fn sample(client_id: u64, request_id: u64, kind: CommandKind) -> CommandSample {
    CommandSample {
        client_id,
        request_id,
        kind: kind.to_wire(),
        ..CommandSample::default()
    }
}

#[test]
fn a_hold_behind_a_flood_goes_first() {
    // Client 1 floods; client 2 sends hold last.
    let mut waiting = vec![w(1, false); 20];
    waiting.push(w(2, true));
    let (picked, _) = pick(&waiting, 0, 8);
    assert_eq!(picked[0], 20, "the hold first: {picked:?}");
    assert_eq!(&picked[1..], &[0, 1, 2, 3, 4, 5, 6]);
}

#[test]
fn a_hold_never_overtakes_its_own_clients_earlier_commands() {
    // Client 1: move, hold. Client 2: status.
    let waiting = [w(1, false), w(2, false), w(1, true)];
    let (picked, _) = pick(&waiting, 0, 8);
    assert_eq!(picked, [0, 1, 2]);
}

#[test]
fn round_robin_one_per_client_per_round() {
    let waiting = [
        w(5, false),
        w(5, false),
        w(5, false),
        w(3, false),
        w(9, false),
    ];
    let (picked, cursor) = pick(&waiting, 0, 4);
    // Ascending client ids from the start: 3, 5, 9, then 5 again.
    assert_eq!(picked, [3, 0, 4, 1]);
    assert_eq!(cursor, 5);
}

#[test]
fn the_start_rotates_after_the_last_client_served() {
    let waiting = [w(1, false), w(2, false), w(3, false)];
    assert_eq!(pick(&waiting, 1, 2), (vec![1, 2], 3));
    assert_eq!(pick(&waiting, 3, 2), (vec![0, 1], 2));
    // A cursor above every waiting client wraps to the lowest.
    assert_eq!(pick(&waiting, 99, 1), (vec![0], 1));
}

#[test]
fn a_client_whose_stop_was_served_waits_for_round_two() {
    // Client 1: hold, status. Client 2: status. Served: hold(1), status(2), status(1).
    let waiting = [w(1, true), w(1, false), w(2, false)];
    let (picked, _) = pick(&waiting, 0, 8);
    assert_eq!(picked, [0, 2, 1]);
}

#[test]
fn intake_serves_in_rounds_and_keeps_the_rest_in_order() {
    let mut intake = Intake::with_capacity(16);
    let incoming = [
        sample(1, 1, CommandKind::Status),
        sample(1, 2, CommandKind::Status),
        sample(2, 1, CommandKind::Status),
        sample(3, 1, CommandKind::Hold),
        sample(1, 3, CommandKind::Status),
    ];
    intake.free()[..incoming.len()].copy_from_slice(&incoming);
    intake.received(incoming.len());
    let ids = |s: &[CommandSample]| {
        s.iter()
            .map(|c| (c.client_id, c.request_id))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        ids(intake.next_cycle()),
        [(3, 1), (1, 1), (2, 1), (1, 2), (1, 3)]
    );
    assert_eq!(intake.waiting(), 0);
    assert!(intake.next_cycle().is_empty());
    assert_eq!(intake.most_waiting(), 5);
}

#[test]
fn a_full_backlog_takes_no_more() {
    let mut intake = Intake::with_capacity(4);
    let n = intake.free().len();
    intake.received(n);
    assert!(intake.free().is_empty());
    intake.received(3);
    assert_eq!(intake.waiting(), 4);
}

#[test]
fn no_waiting_client_starves_over_cycles() {
    // 20 clients with 25 commands each; 8 served per cycle: every client is served at least
    // once in every 3 consecutive cycles.
    let mut intake = Intake::with_capacity(COMMAND_BACKLOG);
    let mut k = 0;
    for r in 0..25 {
        for c in 1..=20 {
            intake.free()[k] = sample(c, r, CommandKind::Status);
            k += 1;
        }
    }
    intake.received(k);
    let mut last_served = [0usize; 21];
    for cycle in 1..=60 {
        for s in intake.next_cycle() {
            last_served[s.client_id as usize] = cycle;
        }
        if cycle >= 3 {
            for (c, &at) in last_served.iter().enumerate().skip(1) {
                assert!(
                    at + 3 > cycle,
                    "client {c} last served at {at}, now {cycle}"
                );
            }
        }
    }
}

proptest! {
    #[test]
    fn selection_is_fair_ordered_and_stops_first(
        clients in proptest::collection::vec((1u64..6, proptest::bool::weighted(0.2)), 0..60),
        cursor in 0u64..7,
        max in 1usize..=8,
    ) {
        let waiting: Vec<Waiting> = clients.iter().map(|&(c, u)| w(c, u)).collect();
        let (picked, next_cursor) = pick(&waiting, cursor, max);
        // Nothing lost or duplicated: as many as allowed, distinct, in range.
        prop_assert_eq!(picked.len(), waiting.len().min(max));
        let mut sorted = picked.clone();
        sorted.sort_unstable();
        sorted.dedup();
        prop_assert_eq!(sorted.len(), picked.len());
        prop_assert!(picked.iter().all(|&i| i < waiting.len()));
        // Per-client order: each client's picks are its oldest samples, in order.
        for c in 1..6 {
            let all: Vec<usize> = (0..waiting.len()).filter(|&i| waiting[i].client_id == c).collect();
            let mine: Vec<usize> = picked.iter().copied().filter(|&i| waiting[i].client_id == c).collect();
            prop_assert_eq!(&all[..mine.len()], &mine[..]);
        }
        // Stops first: the clients whose oldest sample is a stop come before anything else.
        let stop_heads: Vec<usize> = (1..6)
            .filter_map(|c| waiting.iter().position(|x| x.client_id == c))
            .filter(|&i| waiting[i].urgent)
            .collect();
        let lead = stop_heads.len().min(max);
        for &i in &picked[..lead] {
            prop_assert!(stop_heads.contains(&i), "pick {} is not a stop head: {:?}", i, picked);
        }
        // Fairness: when a client gets its k-th sample, every other client has min(k-1, its
        // waiting) already.
        let mut got = [0usize; 6];
        let avail = |c: usize| waiting.iter().filter(|x| x.client_id == c as u64).count();
        for &i in &picked {
            let c = waiting[i].client_id as usize;
            got[c] += 1;
            for other in 1..6 {
                if other != c {
                    prop_assert!(got[other] >= (got[c] - 1).min(avail(other)),
                        "client {} got {} before client {} got {}: {:?}", c, got[c], other, got[other], picked);
                }
            }
        }
        // The cursor is a client served by the round robin, or unchanged.
        prop_assert!(next_cursor == cursor || picked.iter().any(|&i| waiting[i].client_id == next_cursor));
    }

    #[test]
    fn intake_loses_and_duplicates_nothing_over_cycles(
        batches in proptest::collection::vec(
            proptest::collection::vec((1u64..5, proptest::bool::weighted(0.2)), 0..12), 1..20),
    ) {
        let mut intake = Intake::with_capacity(64);
        let mut next_id = [0u64; 5];
        let mut served: Vec<(u64, u64)> = Vec::new();
        let mut sent = 0;
        for batch in &batches {
            let room = intake.free().len();
            let batch = &batch[..batch.len().min(room)];
            for (slot, &(c, urgent)) in intake.free().iter_mut().zip(batch) {
                next_id[c as usize] += 1;
                let kind = if urgent { CommandKind::Hold } else { CommandKind::Status };
                *slot = sample(c, next_id[c as usize], kind);
            }
            intake.received(batch.len());
            sent += batch.len();
            served.extend(intake.next_cycle().iter().map(|s| (s.client_id, s.request_id)));
        }
        while intake.waiting() > 0 {
            let got = intake.next_cycle();
            prop_assert!(!got.is_empty());
            served.extend(got.iter().map(|s| (s.client_id, s.request_id)));
        }
        prop_assert_eq!(served.len(), sent);
        for c in 1..5u64 {
            let ids: Vec<u64> = served.iter().filter(|s| s.0 == c).map(|s| s.1).collect();
            let want: Vec<u64> = (1..=next_id[c as usize]).collect();
            prop_assert_eq!(ids, want, "client {} in order", c);
        }
    }
}
