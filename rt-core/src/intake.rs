//! Command intake: which waiting commands the cycle serves, hold first, then round robin.
//!
//! Runs inside the cycle. Every buffer is allocated once by [`Intake::new`]; afterwards
//! nothing allocates, locks or blocks (the selection sorts in place with `sort_unstable`).
//!
//! Every cycle the edge moves *every* sample waiting in the command service into the backlog
//! ([`Intake::free`], [`Intake::received`]; when the backlog is full the rest stays in
//! iceoryx2's queue), then [`Intake::next_cycle`] chooses at most [`COMMANDS_PER_CYCLE`] of
//! them with [`select`]:
//!
//! 1. every client whose *oldest* waiting sample is `hold` or `client_gone` gets that one first
//!    (a stop jumps ahead of other clients, never ahead of the same client's earlier commands);
//! 2. then round robin over the clients (ascending client id, starting after the client served
//!    last in the previous cycle): one sample per client per round, each client's samples in
//!    their order. A client whose stop was served in step 1 already had its turn in round one.
//!
//! So no client gets a second sample in a cycle before every other waiting client got one, and
//! a flood from one client delays another client's command by at most one round.

use mcm_shared::mode::CommandKind;
use mcm_shared::sample::CommandSample;
use mcm_shared::service::{COMMAND_BACKLOG, COMMANDS_PER_CYCLE};

/// One waiting sample as the selection sees it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Waiting {
    pub client_id: u64,
    /// A stop (`hold` or `client_gone`): served first when it is its client's oldest sample.
    pub urgent: bool,
}

impl Waiting {
    pub fn of(sample: &CommandSample) -> Self {
        Self {
            client_id: sample.client_id,
            urgent: is_urgent(sample.kind),
        }
    }
}

/// A stop ([`CommandKind::is_stop`]) goes out ahead of other clients' commands; an unknown
/// kind is no stop (the controller refuses it in its turn).
pub fn is_urgent(kind: u32) -> bool {
    CommandKind::try_from(kind).is_ok_and(CommandKind::is_stop)
}

/// One client's run of samples in the sorted order.
#[derive(Debug, Clone, Copy, Default)]
struct Group {
    client_id: u64,
    /// Position (in the sorted order) of its next unserved sample, and the end of its run.
    next: u32,
    end: u32,
    /// Its stop was served in step 1 (it had its turn in round one).
    stopped: bool,
}

/// Working space of [`select`], sized once for a number of waiting samples.
pub struct Scratch {
    /// (client id, arrival index), sorted: each client's samples together, in arrival order.
    order: Box<[(u64, u32)]>,
    groups: Box<[Group]>,
}

impl Scratch {
    pub fn new(capacity: usize) -> Self {
        Self {
            order: vec![(0, 0); capacity].into_boxed_slice(),
            groups: vec![Group::default(); capacity].into_boxed_slice(),
        }
    }

    pub fn capacity(&self) -> usize {
        self.order.len()
    }
}

/// Choose up to `picked.len()` of the `waiting` samples (in arrival order): stops first, then
/// round robin starting with the first client whose id is above `cursor` (wrapping). Writes the
/// chosen indices into `picked` in the order they are to be served and returns how many, and
/// the cursor for the next cycle (the last client served by the round robin; unchanged when it
/// served none). Only the first `scratch.capacity()` samples are considered.
pub fn select(
    waiting: &[Waiting],
    cursor: u64,
    scratch: &mut Scratch,
    picked: &mut [usize],
) -> (usize, u64) {
    let n = waiting.len().min(scratch.capacity());
    let order = &mut scratch.order[..n];
    for (i, (slot, w)) in order.iter_mut().zip(waiting).enumerate() {
        *slot = (w.client_id, i as u32);
    }
    order.sort_unstable();
    // The runs of each client, in ascending client id.
    let mut g = 0;
    for (pos, &(client, _)) in order.iter().enumerate() {
        if g == 0 || scratch.groups[g - 1].client_id != client {
            scratch.groups[g] = Group {
                client_id: client,
                next: pos as u32,
                end: pos as u32,
                stopped: false,
            };
            g += 1;
        }
        scratch.groups[g - 1].end = pos as u32 + 1;
    }
    let groups = &mut scratch.groups[..g];
    let first = groups
        .iter()
        .position(|gr| gr.client_id > cursor)
        .unwrap_or(0);
    let mut count = 0;
    let mut next_cursor = cursor;
    // Step 1: stops at the head of their client's samples.
    for j in 0..g {
        if count == picked.len() {
            return (count, next_cursor);
        }
        let gr = &mut groups[(first + j) % g];
        let index = order[gr.next as usize].1 as usize;
        if waiting[index].urgent {
            picked[count] = index;
            count += 1;
            gr.next += 1;
            gr.stopped = true;
        }
    }
    // Step 2: rounds of one sample per client.
    let mut round = 0;
    loop {
        let mut any = false;
        for j in 0..g {
            if count == picked.len() {
                return (count, next_cursor);
            }
            let gr = &mut groups[(first + j) % g];
            if (round == 0 && gr.stopped) || gr.next == gr.end {
                continue;
            }
            picked[count] = order[gr.next as usize].1 as usize;
            count += 1;
            gr.next += 1;
            next_cursor = gr.client_id;
            any = true;
        }
        if !any && round > 0 {
            return (count, next_cursor);
        }
        round += 1;
    }
}

/// The backlog of received commands and this cycle's choice from it.
pub struct Intake {
    backlog: Box<[CommandSample]>,
    len: usize,
    waiting: Box<[Waiting]>,
    taken: Box<[bool]>,
    scratch: Scratch,
    cursor: u64,
    served: [CommandSample; COMMANDS_PER_CYCLE],
    most_waiting: usize,
}

impl Default for Intake {
    fn default() -> Self {
        Self::new()
    }
}

impl Intake {
    /// A backlog of [`COMMAND_BACKLOG`] samples: every publisher's whole buffer.
    pub fn new() -> Self {
        Self::with_capacity(COMMAND_BACKLOG)
    }

    pub fn with_capacity(capacity: usize) -> Self {
        Self {
            backlog: vec![CommandSample::default(); capacity].into_boxed_slice(),
            len: 0,
            waiting: vec![
                Waiting {
                    client_id: 0,
                    urgent: false
                };
                capacity
            ]
            .into_boxed_slice(),
            taken: vec![false; capacity].into_boxed_slice(),
            scratch: Scratch::new(capacity),
            cursor: 0,
            served: [CommandSample::default(); COMMANDS_PER_CYCLE],
            most_waiting: 0,
        }
    }

    /// The free slots of the backlog, to receive into (empty when it is full).
    pub fn free(&mut self) -> &mut [CommandSample] {
        &mut self.backlog[self.len..]
    }

    /// `n` samples were written to the start of [`Intake::free`].
    pub fn received(&mut self, n: usize) {
        self.len = (self.len + n).min(self.backlog.len());
        self.most_waiting = self.most_waiting.max(self.len);
    }

    /// Samples waiting now.
    pub fn waiting(&self) -> usize {
        self.len
    }

    /// The most samples that waited at once so far.
    pub fn most_waiting(&self) -> usize {
        self.most_waiting
    }

    /// Choose this cycle's commands ([`select`]) and take them out of the backlog; the rest
    /// keep their order for the next cycle.
    pub fn next_cycle(&mut self) -> &[CommandSample] {
        let n = self.len;
        for (w, s) in self.waiting[..n].iter_mut().zip(&self.backlog[..n]) {
            *w = Waiting::of(s);
        }
        let mut picked = [0usize; COMMANDS_PER_CYCLE];
        let (count, cursor) = select(
            &self.waiting[..n],
            self.cursor,
            &mut self.scratch,
            &mut picked,
        );
        self.cursor = cursor;
        for (out, &i) in self.served.iter_mut().zip(&picked[..count]) {
            *out = self.backlog[i];
            self.taken[i] = true;
        }
        let mut kept = 0;
        for i in 0..n {
            if self.taken[i] {
                self.taken[i] = false;
            } else {
                self.backlog[kept] = self.backlog[i];
                kept += 1;
            }
        }
        self.len = kept;
        &self.served[..count]
    }
}

#[cfg(test)]
mod tests;
