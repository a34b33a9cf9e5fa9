//! `[gateway.connections]`: limits that keep idle, slow or greedy clients from locking others
//! out of the gateway's two ports (JSON 18010 and the text HMI 18011; each port has its own
//! set of slots). Every key is optional; the defaults are the documented ones below.

use super::super::{ConfigError, finite_ge, invalid};
use serde::Deserialize;

/// Longest timeout accepted for any key (one day) [s].
pub const MAX_TIMEOUT_S: f64 = 86_400.0;
/// Most connections one port may be configured to accept.
pub const MAX_CONNECTIONS_LIMIT: usize = 4096;

/// `[gateway.connections]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ConnectionLimits {
    /// Most simultaneous connections per port (default 64), the loopback reserve included.
    pub max_connections: usize,
    /// Most simultaneous connections per port from one IP address (default 16).
    pub max_per_peer: usize,
    /// Slots of `max_connections` that only loopback peers may use (default 4), so that a
    /// local operator can always connect and send `hold`.
    pub loopback_reserve: usize,
    /// A connection that sends no complete line for this long is closed (default 300 s). A
    /// connection that runs a command (e.g. `calibrate`), holds a torque session or shows
    /// the HMI's `watch` is not idle.
    pub idle_timeout_s: f64,
    /// A JSON line that was started, or a message on the pendant's WebSocket, must be complete
    /// within this long (default 10 s).
    pub line_timeout_s: f64,
    /// The same for a line typed at the text HMI (default 120 s: people type slowly).
    pub hmi_line_timeout_s: f64,
}

impl Default for ConnectionLimits {
    fn default() -> Self {
        Self {
            max_connections: 64,
            max_per_peer: 16,
            loopback_reserve: 4,
            idle_timeout_s: 300.0,
            line_timeout_s: 10.0,
            hmi_line_timeout_s: 120.0,
        }
    }
}

impl ConnectionLimits {
    /// Check every key; the first problem found names its key, value and allowed range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        const P: &str = "gateway.connections";
        let max = self.max_connections;
        if !(1..=MAX_CONNECTIONS_LIMIT).contains(&max) {
            return Err(invalid(
                format!("{P}.max_connections"),
                max,
                format!("1 to {MAX_CONNECTIONS_LIMIT}"),
            ));
        }
        if !(1..=max).contains(&self.max_per_peer) {
            return Err(invalid(
                format!("{P}.max_per_peer"),
                self.max_per_peer,
                format!("1 to max_connections ({max})"),
            ));
        }
        if self.loopback_reserve >= max {
            return Err(invalid(
                format!("{P}.loopback_reserve"),
                self.loopback_reserve,
                format!(
                    "0 to max_connections - 1 ({}), so that remote peers keep at least one slot",
                    max - 1
                ),
            ));
        }
        for (key, v) in [
            ("idle_timeout_s", self.idle_timeout_s),
            ("line_timeout_s", self.line_timeout_s),
            ("hmi_line_timeout_s", self.hmi_line_timeout_s),
        ] {
            if !(finite_ge(v, 1.0) && v <= MAX_TIMEOUT_S) {
                return Err(invalid(
                    format!("{P}.{key}"),
                    v,
                    format!("1 to {MAX_TIMEOUT_S} seconds"),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
