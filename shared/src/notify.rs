//! systemd's service notifications (`sd_notify(3)`), for `mcm-rt` and `mcm-gateway` run as
//! `Type=notify` units (`deploy/systemd/`, docs/deploy.md "systemd"): `READY=1` when the program
//! serves, `STOPPING=1` when its stop begins, `STATUS=` lines for `systemctl status`, and the
//! watchdog's `WATCHDOG=1` when the unit sets `WatchdogSec=`.
//!
//! The datagrams are sent by the `sd-notify` crate. Without `NOTIFY_SOCKET` in the environment
//! (run by hand, by the `mcm` launcher, by a test) every call does nothing. A notification that
//! cannot be sent is said once on stderr and otherwise ignored: the program serves on.
//!
//! Not for the real-time cycle: every call formats and sends a datagram. `mcm-rt` sends from a
//! helper thread of its own (`mcm_rt_core::systemd_notify`), which pings the watchdog only while
//! the cycle counter advances ([`Progress`]).

use sd_notify::NotifyState;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// The notifications of one program (`program` names it in the messages on stderr).
#[derive(Debug)]
pub struct Notifier {
    program: &'static str,
    /// `WATCHDOG_USEC` when it is meant for this process (`WATCHDOG_PID` unset or ours).
    watchdog: Option<Duration>,
    /// Whether a failure was already said on stderr.
    failed: AtomicBool,
}

impl Notifier {
    /// The notifier for this process, as systemd started it (`NOTIFY_SOCKET`, `WATCHDOG_USEC`).
    pub fn from_env(program: &'static str) -> Self {
        Self {
            program,
            watchdog: sd_notify::watchdog_enabled(),
            failed: AtomicBool::new(false),
        }
    }

    /// Whether systemd listens (`NOTIFY_SOCKET` is set).
    pub fn listening() -> bool {
        std::env::var_os("NOTIFY_SOCKET").is_some()
    }

    /// `READY=1`: the program serves; `status` says how, for `systemctl status`.
    pub fn ready(&self, status: &str) {
        self.send(&[NotifyState::Ready, NotifyState::Status(status)]);
    }

    /// `STOPPING=1`: the program's stop began (for `mcm-rt`: the controlled stop).
    pub fn stopping(&self, status: &str) {
        self.send(&[NotifyState::Stopping, NotifyState::Status(status)]);
    }

    /// A `STATUS=` line alone.
    pub fn status(&self, status: &str) {
        self.send(&[NotifyState::Status(status)]);
    }

    /// `WATCHDOG=1`: the program is alive. Only worth sending when [`Self::watchdog_every`]
    /// is `Some`.
    pub fn watchdog(&self) {
        self.send(&[NotifyState::Watchdog]);
    }

    /// How often to ping the watchdog: half of the unit's `WatchdogSec=`, as `sd_watchdog_enabled(3)`
    /// advises; `None` when the unit sets no watchdog (or set it for another process).
    pub fn watchdog_every(&self) -> Option<Duration> {
        ping_interval(self.watchdog)
    }

    fn send(&self, states: &[NotifyState]) {
        if let Err(e) = sd_notify::notify(states)
            && !self.failed.swap(true, Ordering::Relaxed)
        {
            let socket = std::env::var_os("NOTIFY_SOCKET").unwrap_or_default();
            eprintln!(
                "{}: cannot notify systemd through NOTIFY_SOCKET={} ({e}); serving on without \
                 its notifications (further failures are not repeated)",
                self.program,
                socket.to_string_lossy()
            );
        }
    }
}

/// Half of the watchdog timeout `timeout` (`None`, or zero: no watchdog).
pub fn ping_interval(timeout: Option<Duration>) -> Option<Duration> {
    timeout.filter(|t| !t.is_zero()).map(|t| t / 2)
}

/// Whether a counter advanced since the last look: the watchdog of `mcm-rt` is pinged only
/// when the cycle counter moved, so that a cycle that hangs stops the pings and systemd's
/// watchdog ends the process.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progress {
    last: u64,
}

impl Progress {
    /// Start from the counter's value `now`.
    pub fn new(now: u64) -> Self {
        Self { last: now }
    }

    /// Whether the counter moved from the last look to `now`; `now` becomes the last look.
    pub fn advanced(&mut self, now: u64) -> bool {
        let moved = now != self.last;
        self.last = now;
        moved
    }
}

#[cfg(test)]
mod tests;
