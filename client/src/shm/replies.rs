//! Finding replies in the reply blocks of the state blackboard.
//!
//! The core numbers every reply (1, 2, ...) and keeps the newest `REPLY_BLOCKS * REPLY_BLOCK`
//! (8192) readable; the state's `reply_head` is the newest. A reader keeps the last number it
//! has read and reads on to the head, copying each block once, and takes the replies that are
//! its own (by `client_id`: a client its own id, the gateway the ids of its connections). A
//! reply whose slot already holds a newer one was overwritten: whoever it answered will never
//! see it, so a request still waiting for it has an unknown outcome.

#[cfg(test)]
mod tests;

use mcm_shared::sample::{
    REPLY_BLOCK, REPLY_BLOCKS, Reply, ReplyBlock, ReplyEntries, reply_location,
};

/// Replies kept readable by the core.
pub const KEPT: u64 = (REPLY_BLOCKS * REPLY_BLOCK) as u64;

/// What one read found besides the replies.
#[derive(Debug, Default, PartialEq)]
pub struct Scan {
    /// Replies numbered in the read range that could no longer be read.
    pub overwritten: u64,
}

/// The reply blocks of one reader, and the number of the last reply it read.
pub struct Replies {
    entries: ReplyEntries,
    seen: u64,
}

impl Replies {
    /// The blocks `entries` (the block of key `k` at `k - 1`), nothing read yet.
    pub fn new(entries: ReplyEntries) -> Replies {
        Replies { entries, seen: 0 }
    }

    /// The number of the last reply read.
    pub fn seen(&self) -> u64 {
        self.seen
    }

    /// Read on after reply `head` (those before answer nobody waiting: a client that just
    /// connected, a core that just (re)started).
    pub fn skip_to(&mut self, head: u64) {
        self.seen = head;
    }

    /// Hand every reply after the last one read up to `head` (the state's `reply_head`) to
    /// `each`, in order; what was lost on the way.
    pub fn read_to(&mut self, head: u64, each: impl FnMut(&Reply)) -> Scan {
        let entries = &self.entries;
        let scan = scan(
            self.seen,
            head,
            |key| *entries[key as usize - 1].get(),
            each,
        );
        self.seen = head;
        scan
    }
}

/// Read the replies after `seen` up to `head`, each to `each`; `block(key)` gives the block of
/// that key as it is now (read once per block and read).
pub fn scan(
    seen: u64,
    head: u64,
    mut block: impl FnMut(u32) -> ReplyBlock,
    mut each: impl FnMut(&Reply),
) -> Scan {
    let mut out = Scan::default();
    if head <= seen {
        // Nothing new (or the core restarted and numbers from 1 again).
        return out;
    }
    let oldest = head.saturating_sub(KEPT - 1).max(1);
    let first = (seen + 1).max(oldest);
    out.overwritten = first - (seen + 1);
    // Keys start at 1: key 0 is no block read yet.
    let mut current = (0, ReplyBlock::default());
    for n in first..=head {
        let (key, _) = reply_location(n);
        if current.0 != key {
            current = (key, block(key));
        }
        match current.1.reply(n) {
            Some(r) => each(r),
            // Overwritten while being read (the core wrote more than the blocks hold).
            None => out.overwritten += 1,
        }
    }
    out
}
