//! Finding this client's replies in the reply blocks of the state blackboard.
//!
//! The core numbers every reply (1, 2, ...) and keeps the newest `REPLY_BLOCKS * REPLY_BLOCK`
//! (8192) readable; the state's `reply_head` is the newest. A client keeps the last number it
//! has read and reads on to the head, taking the replies whose `client_id` is its own. A reply
//! whose slot already holds a newer one was overwritten: whoever it answered will never see
//! it, so a request of this client still waiting then has an unknown outcome.

use mcm_shared::sample::{REPLY_BLOCK, REPLY_BLOCKS, Reply};

/// Replies kept readable by the core.
pub const KEPT: u64 = (REPLY_BLOCKS * REPLY_BLOCK) as u64;

/// What one scan found.
#[derive(Debug, Default, PartialEq)]
pub struct Scan {
    /// Replies numbered in the scanned range that could no longer be read.
    pub overwritten: u64,
}

/// Read the replies after `seen` up to `head`; hand those to `client_id` to `mine`. `read(n)`
/// gives reply `n` if its slot still holds it. Returns the new `seen` (= `head`) and what was
/// lost on the way.
pub fn scan(
    seen: u64,
    head: u64,
    client_id: u64,
    read: impl Fn(u64) -> Option<Reply>,
    mut mine: impl FnMut(Reply),
) -> (u64, Scan) {
    let mut out = Scan::default();
    if head <= seen {
        // Nothing new (or the core restarted and numbers from 1 again).
        return (head, out);
    }
    let oldest = head.saturating_sub(KEPT - 1).max(1);
    let first = (seen + 1).max(oldest);
    out.overwritten = first - (seen + 1);
    for n in first..=head {
        match read(n) {
            Some(r) if r.client_id == client_id => mine(r),
            Some(_) => {}
            None => out.overwritten += 1,
        }
    }
    (head, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reply(seq: u64, client_id: u64) -> Reply {
        Reply {
            seq,
            client_id,
            request_id: seq * 10,
            ..Reply::default()
        }
    }

    #[test]
    fn only_this_clients_replies_are_taken_in_order() {
        let mut got = Vec::new();
        let (seen, s) = scan(
            2,
            6,
            7,
            |n| Some(reply(n, if n % 2 == 0 { 7 } else { 8 })),
            |r| got.push(r.request_id),
        );
        assert_eq!((seen, s.overwritten), (6, 0));
        assert_eq!(got, [40, 60]);
    }

    #[test]
    fn a_reader_too_far_behind_counts_the_replies_it_lost() {
        let head = KEPT + 100;
        let mut got = 0;
        // Fell 100 + 10 replies behind the ring: the first 100 are gone by number, and 10 more
        // were overwritten while being read.
        let (seen, s) = scan(0, head, 7, |n| (n > 110).then(|| reply(n, 7)), |_| got += 1);
        assert_eq!(seen, head);
        assert_eq!(s.overwritten, 110);
        assert_eq!(got, KEPT - 10);
    }

    #[test]
    fn nothing_new_reads_nothing() {
        let (seen, s) = scan(5, 5, 7, |_| panic!("no read"), |_| panic!("no reply"));
        assert_eq!((seen, s), (5, Scan::default()));
        // A restarted core numbers from 1 again: follow it.
        let (seen, _) = scan(500, 3, 7, |_| panic!("no read"), |_| panic!("no reply"));
        assert_eq!(seen, 3);
    }
}
