//! `[gateway.web]`: the browser pendant (docs/web.md). The gateway serves a page and a
//! WebSocket on its own port (default 18014, the launcher's `--http-port`), with the same bind
//! address and access rules as the JSON port. On by default; `enabled = false` switches it off.

use super::super::{ConfigError, invalid};
use serde::Deserialize;

/// Fewest and most state frames per second a page may be sent.
pub const RATE_HZ_RANGE: std::ops::RangeInclusive<u32> = 1..=100;
/// Most connections from one peer the web port may be configured to admit.
pub const MAX_PER_PEER_LIMIT: usize = 1024;

/// `[gateway.web]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct WebConfig {
    /// Serve the pendant (default true).
    pub enabled: bool,
    /// State frames per second sent to each page (default 30; 1..=100), decimated from the
    /// cycle: each frame is the newest state, a slow page skips frames.
    pub rate_hz: u32,
    /// Most simultaneous connections of the web port from one IP address (default 64): a
    /// browser opens several for one page (the page's assets and its WebSocket), and an
    /// operator's machine may show several pages. The port's total and the loopback reserve
    /// are those of `[gateway.connections]`.
    pub max_per_peer: usize,
}

impl Default for WebConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            rate_hz: 30,
            max_per_peer: 64,
        }
    }
}

impl WebConfig {
    /// Check every key; the first problem found names its key, value and what is allowed.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if !RATE_HZ_RANGE.contains(&self.rate_hz) {
            return Err(invalid(
                "gateway.web.rate_hz",
                self.rate_hz,
                format!(
                    "{}..={} state frames per second",
                    RATE_HZ_RANGE.start(),
                    RATE_HZ_RANGE.end()
                ),
            ));
        }
        if !(1..=MAX_PER_PEER_LIMIT).contains(&self.max_per_peer) {
            return Err(invalid(
                "gateway.web.max_per_peer",
                self.max_per_peer,
                format!("1..={MAX_PER_PEER_LIMIT} connections"),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
