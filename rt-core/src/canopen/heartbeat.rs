//! Heartbeat consumer (one per drive) and the master's heartbeat producer (CiA 301 error
//! control).
//!
//! Runs inside the cycle: plain counters over the caller's `now_ns`, no allocation.
//!
//! The consumer is *armed* by the first heartbeat it sees (or by [`HeartbeatConsumer::arm`]);
//! from then on, a heartbeat missing for `timeout` or longer is reported once by
//! [`HeartbeatConsumer::check`], at exactly `last_seen + timeout`.
//!
//! ```
//! use mcm_rt_core::canopen::heartbeat::HeartbeatConsumer;
//! use mcm_rt_core::canopen::nmt::NmtState;
//! let mut hb = HeartbeatConsumer::new(150_000_000);
//! hb.on_heartbeat(0, NmtState::Operational);
//! assert!(!hb.check(149_999_999));
//! assert!(hb.check(150_000_000));
//! ```

use super::nmt::{NmtState, heartbeat_frame};
use mcm_bus::Frame;

/// Watches the heartbeat of one node.
#[derive(Debug, Clone)]
pub struct HeartbeatConsumer {
    timeout_ns: u64,
    last_seen_ns: Option<u64>,
    state: Option<NmtState>,
    timed_out: bool,
}

impl HeartbeatConsumer {
    pub fn new(timeout_ns: u64) -> HeartbeatConsumer {
        HeartbeatConsumer {
            timeout_ns,
            last_seen_ns: None,
            state: None,
            timed_out: false,
        }
    }

    pub fn timeout_ns(&self) -> u64 {
        self.timeout_ns
    }

    /// Forget everything (the node rebooted).
    pub fn reset(&mut self) {
        self.last_seen_ns = None;
        self.state = None;
        self.timed_out = false;
    }

    /// Start monitoring at `now_ns` even though no heartbeat was seen yet (grace period of
    /// one timeout). Does nothing if a heartbeat was already seen.
    pub fn arm(&mut self, now_ns: u64) {
        if self.last_seen_ns.is_none() {
            self.last_seen_ns = Some(now_ns);
        }
    }

    /// A heartbeat (or boot-up) frame of the node arrived.
    pub fn on_heartbeat(&mut self, now_ns: u64, state: NmtState) {
        self.last_seen_ns = Some(now_ns);
        self.state = Some(state);
        self.timed_out = false;
    }

    /// The last reported NMT state.
    pub fn state(&self) -> Option<NmtState> {
        self.state
    }

    pub fn last_seen_ns(&self) -> Option<u64> {
        self.last_seen_ns
    }

    /// Armed and the last heartbeat is younger than the timeout.
    pub fn is_fresh(&self, now_ns: u64) -> bool {
        self.last_seen_ns
            .is_some_and(|t| now_ns.saturating_sub(t) < self.timeout_ns)
    }

    pub fn is_timed_out(&self) -> bool {
        self.timed_out
    }

    /// `true` exactly once when the armed heartbeat has been missing for `timeout` or longer.
    pub fn check(&mut self, now_ns: u64) -> bool {
        let Some(t) = self.last_seen_ns else {
            return false;
        };
        if !self.timed_out && now_ns.saturating_sub(t) >= self.timeout_ns {
            self.timed_out = true;
            return true;
        }
        false
    }
}

/// Produces the master's own heartbeat `700+id#05` every `period`, starting with the first
/// call of [`HeartbeatProducer::poll`].
#[derive(Debug, Clone)]
pub struct HeartbeatProducer {
    node: u8,
    period_ns: u64,
    next_due_ns: Option<u64>,
}

impl HeartbeatProducer {
    pub fn new(node: u8, period_ns: u64) -> HeartbeatProducer {
        HeartbeatProducer {
            node,
            period_ns: period_ns.max(1),
            next_due_ns: None,
        }
    }

    /// The heartbeat frame when one is due at `now_ns`. The schedule stays on the grid
    /// `start + k * period`; if calls were missed, one frame is sent and the grid skips ahead.
    pub fn poll(&mut self, now_ns: u64) -> Option<Frame> {
        let due = *self.next_due_ns.get_or_insert(now_ns);
        if now_ns < due {
            return None;
        }
        let periods = (now_ns - due) / self.period_ns + 1;
        self.next_due_ns = Some(due + periods * self.period_ns);
        Some(heartbeat_frame(self.node, NmtState::Operational))
    }
}

#[cfg(test)]
mod tests;
