//! Which command sample the bridge publishes next: pure bookkeeping, no I/O.
//!
//! Every connection (client id) has its own queue of jobs; the bridge publishes one sample at a
//! time, taking the connections in turn (round robin), so a connection streaming long
//! `pvt_points` batches delays another one by at most one sample per turn. Urgent jobs (`hold`
//! and `client_gone`) have one queue of their own that is served before every other.
//!
//! Samples published and not yet answered ("in flight") are capped so that the core's command
//! buffer ([`COMMAND_BUFFER`] samples per publisher) can never overflow, whatever the clients
//! do: ordinary samples at most [`ORDINARY_IN_FLIGHT`] in total and [`PER_CLIENT_IN_FLIGHT`]
//! per connection; urgent samples may use the room up to [`ALL_IN_FLIGHT`], so at least
//! `ALL_IN_FLIGHT - ORDINARY_IN_FLIGHT` places are always free for them.

use mcm_shared::service::{COMMAND_BUFFER, COMMANDS_PER_CYCLE};
use std::collections::{HashMap, VecDeque};

/// Samples in flight at most, urgent ones included (below the core's command buffer).
pub(super) const ALL_IN_FLIGHT: usize = COMMAND_BUFFER - 1;
/// Ordinary samples in flight at most, all connections together.
pub(super) const ORDINARY_IN_FLIGHT: usize = COMMAND_BUFFER / 2;
/// Ordinary samples in flight at most for one connection (what the core serves in one cycle).
pub(super) const PER_CLIENT_IN_FLIGHT: usize = COMMANDS_PER_CYCLE;

const _: () = assert!(ORDINARY_IN_FLIGHT < ALL_IN_FLIGHT && ALL_IN_FLIGHT < COMMAND_BUFFER);

/// Permission to publish one sample of the job at the front of a queue.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Grant {
    pub(super) client: u64,
    pub(super) urgent: bool,
}

/// The queues and the in-flight counts.
pub(super) struct Scheduler<T> {
    urgent: VecDeque<(u64, T)>,
    queues: HashMap<u64, VecDeque<T>>,
    /// Connections with queued ordinary jobs, in the order of their next turn.
    ring: VecDeque<u64>,
    in_flight: HashMap<u64, usize>,
    ordinary: usize,
    urgent_in_flight: usize,
}

impl<T> Default for Scheduler<T> {
    fn default() -> Self {
        Self {
            urgent: VecDeque::new(),
            queues: HashMap::new(),
            ring: VecDeque::new(),
            in_flight: HashMap::new(),
            ordinary: 0,
            urgent_in_flight: 0,
        }
    }
}

impl<T> Scheduler<T> {
    /// Queue a job of `client`.
    pub(super) fn push(&mut self, client: u64, job: T, urgent: bool) {
        if urgent {
            self.urgent.push_back((client, job));
            return;
        }
        let q = self.queues.entry(client).or_default();
        if q.is_empty() {
            self.ring.push_back(client);
        }
        q.push_back(job);
    }

    /// Whether no job is queued.
    #[cfg(test)]
    pub(super) fn is_empty(&self) -> bool {
        self.urgent.is_empty() && self.ring.is_empty()
    }

    /// Samples in flight, all together.
    pub(super) fn in_flight(&self) -> usize {
        self.ordinary + self.urgent_in_flight
    }

    /// Whose sample goes out next, if any may: the urgent queue first (while fewer than
    /// [`ALL_IN_FLIGHT`] are in flight), then the next connection in turn that is below its
    /// cap (while fewer than [`ORDINARY_IN_FLIGHT`] ordinary samples are in flight). A
    /// connection that got a grant takes its next turn after every other one.
    pub(super) fn next(&mut self) -> Option<Grant> {
        if let Some((client, _)) = self.urgent.front()
            && self.in_flight() < ALL_IN_FLIGHT
        {
            return Some(Grant {
                client: *client,
                urgent: true,
            });
        }
        if self.ordinary >= ORDINARY_IN_FLIGHT {
            return None;
        }
        for _ in 0..self.ring.len() {
            let client = self.ring.pop_front()?;
            self.ring.push_back(client);
            if self.in_flight.get(&client).copied().unwrap_or(0) < PER_CLIENT_IN_FLIGHT {
                return Some(Grant {
                    client,
                    urgent: false,
                });
            }
        }
        None
    }

    /// The job a grant is for.
    pub(super) fn job(&mut self, g: Grant) -> Option<&mut T> {
        if g.urgent {
            self.urgent.front_mut().map(|(_, j)| j)
        } else {
            self.queues.get_mut(&g.client)?.front_mut()
        }
    }

    /// One sample of the granted job went out.
    pub(super) fn sent(&mut self, g: Grant) {
        if g.urgent {
            self.urgent_in_flight += 1;
        } else {
            self.ordinary += 1;
            *self.in_flight.entry(g.client).or_default() += 1;
        }
    }

    /// A sample sent for `client` was answered (or given up on).
    pub(super) fn answered(&mut self, client: u64, urgent: bool) {
        if urgent {
            self.urgent_in_flight = self.urgent_in_flight.saturating_sub(1);
            return;
        }
        self.ordinary = self.ordinary.saturating_sub(1);
        if let Some(n) = self.in_flight.get_mut(&client) {
            *n = n.saturating_sub(1);
            if *n == 0 {
                self.in_flight.remove(&client);
            }
        }
    }

    /// Take the granted job out of its queue (all of it was sent, or it is given up).
    pub(super) fn finish(&mut self, g: Grant) -> Option<T> {
        if g.urgent {
            return self.urgent.pop_front().map(|(_, j)| j);
        }
        let q = self.queues.get_mut(&g.client)?;
        let job = q.pop_front();
        if q.is_empty() {
            self.queues.remove(&g.client);
            self.ring.retain(|c| *c != g.client);
        }
        job
    }

    /// Take every queued job out (the core is gone); in-flight counts are forgotten too.
    pub(super) fn drain(&mut self) -> Vec<T> {
        let mut out: Vec<T> = self.urgent.drain(..).map(|(_, j)| j).collect();
        for client in self.ring.drain(..) {
            if let Some(q) = self.queues.remove(&client) {
                out.extend(q);
            }
        }
        self.queues.clear();
        self.forget_in_flight();
        out
    }

    /// Nothing is in flight any more (the core that had the samples stopped).
    pub(super) fn forget_in_flight(&mut self) {
        self.in_flight.clear();
        self.ordinary = 0;
        self.urgent_in_flight = 0;
    }
}

#[cfg(test)]
mod tests;
