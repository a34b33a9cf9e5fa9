//! What a connection tells its client about the MCM's own life: the gateway shutting down
//! (the last line before it closes), and the real-time core starting its controlled stop or
//! no longer publishing its state. Runs in the gateway's async tasks, not in the cycle.
//!
//! Each connection watches the core with its own [`CoreWatch`], which looks at the newest
//! state ([`crate::bridge::Bridge::watch_state`]) every [`CORE_CHECK`] (a connection does not
//! wake at the cycle rate) and yields a notice on a change worth telling.

use mcm_shared::sample::{STATE_SHUTTING_DOWN, StateSample};
use serde_json::Value;
use std::time::Duration;
use tokio::sync::watch;

/// How often a connection looks at the core's state.
pub const CORE_CHECK: Duration = Duration::from_millis(100);

/// The last result a client gets when the gateway shuts down.
pub fn gateway_stopping() -> Value {
    crate::result::error(
        "the MCM is shutting down (the gateway was asked to stop); closing this connection",
    )
}

/// The notice when the core starts its controlled stop.
pub const RT_STOPPING: &str = "mcm-rt is shutting down (it was asked to stop): the arm is brought \
     to standstill, held, then the drives are disabled; every command but status is refused";
/// The notice when a core that was shutting down stopped publishing.
pub const RT_STOPPED: &str = "mcm-rt stopped after its controlled stop (arm at standstill, drives \
     disabled); commands fail until it runs again";
/// The notice when a running core stopped publishing without a shutdown.
pub const RT_VANISHED: &str = "mcm-rt stopped publishing its state without shutting down (killed \
     or crashed); the drives stop on their heartbeat timeout; commands fail until it runs again";

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
fn notice(from: Seen, to: Seen) -> Option<&'static str> {
    match (from, to) {
        (Seen::Running | Seen::Gone, Seen::ShuttingDown) => Some(RT_STOPPING),
        (Seen::ShuttingDown, Seen::Gone) => Some(RT_STOPPED),
        (Seen::Running, Seen::Gone) => Some(RT_VANISHED),
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

    /// The next notice for the client: a `generic` ERROR result. Cancel-safe.
    pub async fn next(&mut self) -> Value {
        loop {
            self.tick.tick().await;
            let now = seen(self.state.borrow().as_deref());
            let from = std::mem::replace(&mut self.last, now);
            if let Some(text) = notice(from, now) {
                return crate::result::error(text);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(flags: u32) -> Option<Box<StateSample>> {
        Some(Box::new(StateSample {
            flags,
            ..StateSample::default()
        }))
    }

    #[tokio::test]
    async fn a_shutdown_then_silence_gives_two_notices_in_order() {
        let (tx, rx) = watch::channel(sample(0));
        let mut w = CoreWatch::new(rx);
        tx.send_replace(sample(STATE_SHUTTING_DOWN));
        assert_eq!(w.next().await["error_message"], RT_STOPPING);
        tx.send_replace(None);
        assert_eq!(w.next().await["error_message"], RT_STOPPED);
        tx.send_replace(sample(0));
        let quiet = tokio::time::timeout(CORE_CHECK * 5, w.next()).await;
        assert!(quiet.is_err(), "a core appearing is no error: {quiet:?}");
    }

    #[tokio::test]
    async fn a_core_that_vanishes_is_told_as_such() {
        let (tx, rx) = watch::channel(sample(0));
        let mut w = CoreWatch::new(rx);
        tx.send_replace(None);
        let v = w.next().await;
        assert_eq!(v["result_type"], "generic");
        assert_eq!(v["error_status"], "ERROR");
        assert_eq!(v["error_message"], RT_VANISHED);
    }
}
