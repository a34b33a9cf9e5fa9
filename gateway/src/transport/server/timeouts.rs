//! The time limits of a TCP connection, the same for the JSON port and the text HMI: the idle
//! and line timeouts of `[gateway.connections]` ([`deadline`], [`Expiry`]) and the longest
//! wait for a client to take its output ([`WRITE_TIMEOUT`]). Runs in the gateway's async
//! tasks, not in the real-time cycle.

use mcm_shared::config::ConnectionLimits;
use std::time::Duration;
use tokio::time::Instant;

/// Longest wait for a client to take what is written to it (a result line, the HMI's output);
/// a client that reads nothing for that long is closed.
pub const WRITE_TIMEOUT: Duration = Duration::from_secs(30);

/// Which timeout of `[gateway.connections]` ends a connection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Expiry {
    /// `idle_timeout_s`: no complete line for that long.
    Idle,
    /// `line_timeout_s` (JSON) or `hmi_line_timeout_s` (HMI): a started line not completed.
    Line,
}

impl Expiry {
    /// Its `error_code`.
    pub fn code(self) -> mcm_shared::error_code::ErrorCode {
        match self {
            Expiry::Idle => mcm_shared::error_code::ErrorCode::IdleTimeout,
            Expiry::Line => mcm_shared::error_code::ErrorCode::LineTimeout,
        }
    }

    /// The reason given to the client, naming the timeout, its value and its key.
    pub fn message(self, limits: &ConnectionLimits, hmi: bool) -> String {
        let (who, key, value) = match (self, hmi) {
            (Expiry::Idle, false) => ("connection", "idle_timeout_s", limits.idle_timeout_s),
            (Expiry::Idle, true) => ("session", "idle_timeout_s", limits.idle_timeout_s),
            (Expiry::Line, false) => ("connection", "line_timeout_s", limits.line_timeout_s),
            (Expiry::Line, true) => ("session", "hmi_line_timeout_s", limits.hmi_line_timeout_s),
        };
        let what = match self {
            Expiry::Idle => "idle timeout: no command",
            Expiry::Line => "line timeout: a command line was started but not completed",
        };
        let within = if self == Expiry::Idle {
            "for"
        } else {
            "within"
        };
        format!("{what} {within} {value} s (gateway.connections.{key}); closing the {who}")
    }
}

/// `s` seconds after `t`; `None` if that is not a time (a value validation would refuse).
fn after(t: Instant, s: f64) -> Option<Instant> {
    Duration::try_from_secs_f64(s)
        .ok()
        .and_then(|d| t.checked_add(d))
}

/// The idle or the line timeout, whichever ends first. `idle_since`: since when the connection
/// has been idle; `line_start`: when its unfinished line began; `line_timeout_s`: the port's.
pub fn deadline(
    limits: &ConnectionLimits,
    idle_since: Instant,
    line_start: Option<Instant>,
    line_timeout_s: f64,
) -> Option<(Instant, Expiry)> {
    let idle = after(idle_since, limits.idle_timeout_s).map(|t| (t, Expiry::Idle));
    let line = line_start
        .and_then(|s| after(s, line_timeout_s))
        .map(|t| (t, Expiry::Line));
    match (idle, line) {
        (Some(i), Some(l)) => Some(if l.0 < i.0 { l } else { i }),
        (i, l) => i.or(l),
    }
}
