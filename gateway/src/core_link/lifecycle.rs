//! What a connection tells its client about the MCM's own life: the gateway shutting down
//! (the last line before it closes), and the real-time core starting its controlled stop or
//! no longer publishing its state. Runs in the gateway's async tasks, not in the cycle.
//!
//! Each connection watches the core with its own [`CoreWatch`], which looks at the newest state
//! ([`crate::core_link::bridge::Bridge::watch_state`]) every [`CORE_CHECK`] (a connection does
//! not wake at the cycle rate) and yields a notice on a change worth telling.
//!
//! The gateway is usually stopped *because* the core stopped: the launcher stops it when
//! `mcm-rt` dies or after its controlled stop, and so does systemd (the unit's `BindsTo=` and
//! `Before=mcm-rt.service`: stopped with the core, after it), both within milliseconds, before
//! the bridge has seen the core fall silent. So on shutdown the gateway first [`settle`]s what
//! is known of the core, once for every transport (`crate::run`), and each connection and the
//! ZeroMQ PUB socket send the notice still due ([`CoreWatch::due`]) before their last line: a
//! client hears that the core stopped (or vanished), not only that the gateway was asked to
//! stop.
//!
//! A notice is a [`Notice`], the same words on every channel: JSON/TCP and ZeroMQ send it as a
//! `generic` ERROR result ([`Notice::result`]), the HMI prints it as an ERROR line.

use mcm_shared::sample::{STATE_SHUTTING_DOWN, StateSample};
use serde_json::Value;
use std::time::Duration;
use tokio::sync::watch;

/// How often a connection looks at the core's state.
pub const CORE_CHECK: Duration = Duration::from_millis(100);

/// A notice about the MCM's own life.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Notice {
    /// The core starts its controlled stop.
    RtStopping,
    /// A core that was shutting down stopped publishing.
    RtStopped,
    /// A running core stopped publishing without a shutdown.
    RtVanished,
    /// The gateway shuts down: the last words a client gets.
    GatewayStopping,
}

impl Notice {
    /// The words, the same on every channel.
    pub fn text(self) -> &'static str {
        match self {
            Notice::RtStopping => {
                "mcm-rt is shutting down (it was asked to stop): the arm is brought to standstill, \
                 held, then the drives are disabled; every command but status is refused"
            }
            Notice::RtStopped => {
                "mcm-rt stopped after its controlled stop (arm at standstill, drives disabled); \
                 commands fail until it runs again"
            }
            Notice::RtVanished => {
                "mcm-rt stopped publishing its state without shutting down (killed or crashed); \
                 the drives stop on their heartbeat timeout; commands fail until it runs again"
            }
            Notice::GatewayStopping => {
                "the MCM is shutting down (the gateway was asked to stop); closing this connection"
            }
        }
    }

    /// Its `error_code`.
    pub fn code(self) -> mcm_shared::error_code::ErrorCode {
        use mcm_shared::error_code::ErrorCode;
        match self {
            Notice::RtStopping => ErrorCode::CoreStopping,
            Notice::GatewayStopping => ErrorCode::GatewayStopping,
            Notice::RtStopped => ErrorCode::CoreStopped,
            Notice::RtVanished => ErrorCode::CoreVanished,
        }
    }

    /// As the JSON/TCP port and ZeroMQ send it: a `generic` ERROR result.
    pub fn result(self) -> Value {
        crate::command::result::error(self.code(), self.text())
    }
}

/// Longest wait of [`settle`]: more than the bridge takes to call a silent core stopped (its
/// state unchanged for 0.5 s, see `bridge/worker.rs`), with room for a loaded machine.
pub const SETTLE_WAIT: Duration = Duration::from_secs(2);

/// Wait until what is known of the core is current: two new states came (the core runs), or
/// the bridge found it silent and said so (`None`); at most [`SETTLE_WAIT`]. One new state
/// proves nothing: the bridge may not have read the last state a killed core published yet.
/// Returns at once when no core is known to run. Used once on shutdown, before any client is
/// told.
pub async fn settle(mut state: watch::Receiver<Option<Box<StateSample>>>) {
    if state.borrow_and_update().is_none() {
        return;
    }
    let known = async {
        let mut fresh = 0;
        while state.changed().await.is_ok() {
            if state.borrow_and_update().is_none() {
                return;
            }
            fresh += 1;
            if fresh == 2 {
                return;
            }
        }
    };
    let _ = tokio::time::timeout(SETTLE_WAIT, known).await;
}

/// What a connection last knew of the core.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Seen {
    Gone,
    Running,
    ShuttingDown,
}

fn seen(state: Option<&StateSample>) -> Seen {
    match state {
        None => Seen::Gone,
        Some(s) if s.flags & STATE_SHUTTING_DOWN != 0 => Seen::ShuttingDown,
        Some(_) => Seen::Running,
    }
}

/// The notice for a change of what is known of the core; `None` for changes not worth an
/// ERROR (the core appearing).
fn notice(from: Seen, to: Seen) -> Option<Notice> {
    match (from, to) {
        (Seen::Running | Seen::Gone, Seen::ShuttingDown) => Some(Notice::RtStopping),
        (Seen::ShuttingDown, Seen::Gone) => Some(Notice::RtStopped),
        (Seen::Running, Seen::Gone) => Some(Notice::RtVanished),
        _ => None,
    }
}

/// One connection's watch on the core.
pub struct CoreWatch {
    state: watch::Receiver<Option<Box<StateSample>>>,
    last: Seen,
    tick: tokio::time::Interval,
}

impl CoreWatch {
    /// Start from what is known now (no notice for it).
    pub fn new(state: watch::Receiver<Option<Box<StateSample>>>) -> Self {
        let last = seen(state.borrow().as_deref());
        let mut tick = tokio::time::interval(CORE_CHECK);
        tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
        Self { state, last, tick }
    }

    /// The next notice for the client. Cancel-safe.
    pub async fn next(&mut self) -> Notice {
        loop {
            self.tick.tick().await;
            if let Some(v) = self.due() {
                return v;
            }
        }
    }

    /// The notice due now, without waiting for the next check (on shutdown, after
    /// [`settle`], before the last line); `None` when the client knows the core's state.
    pub fn due(&mut self) -> Option<Notice> {
        let now = seen(self.state.borrow().as_deref());
        let from = std::mem::replace(&mut self.last, now);
        notice(from, now)
    }

    /// The last notices a client gets when the gateway shuts down (after [`settle`]): the one
    /// about the core still due, if any, then [`Notice::GatewayStopping`].
    pub fn last_words(&mut self) -> impl Iterator<Item = Notice> + use<> {
        self.due().into_iter().chain([Notice::GatewayStopping])
    }
}

#[cfg(test)]
mod tests;
