//! `[gateway.web]`: the browser pendant (docs/web.md). The gateway serves a page and a
//! WebSocket on its own port (default 18014, the launcher's `--http-port`), with the same bind
//! address and access rules as the JSON port. On by default; `enabled = false` switches it off.
//! It answers only requests addressed to one of the robot's own names ([`WebConfig::hosts`]).

use super::super::{ConfigError, invalid};
use serde::Deserialize;

mod host;
pub use host::HostName;

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
    /// The names the pendant is reached by besides `localhost`, the loopback addresses and the
    /// machine's own addresses (default none): DNS names of the robot, or the name a reverse
    /// proxy forwards in `Host`. A request whose `Host` is none of them is refused (DNS
    /// rebinding, docs/security.md).
    pub allowed_hosts: Vec<String>,
}

impl Default for WebConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            rate_hz: 30,
            max_per_peer: 64,
            allowed_hosts: Vec::new(),
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
        self.hosts().map(|_| ())
    }

    /// The configured `allowed_hosts`, each a DNS name or an IP address.
    pub fn hosts(&self) -> Result<Vec<HostName>, ConfigError> {
        self.allowed_hosts
            .iter()
            .enumerate()
            .map(|(i, s)| {
                HostName::parse(s).map_err(|why| {
                    invalid(
                        format!("gateway.web.allowed_hosts[{i}]"),
                        format!("{s:?}"),
                        format!(
                            "a DNS name or an IP address without scheme or port, e.g. \
                             \"robot-7.cell.example\" or \"10.17.0.5\" ({why})"
                        ),
                    )
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests;
