//! `[gateway.zmq]`: the gateway's ZeroMQ interface (off by default). A ROUTER socket takes the
//! same JSON commands as the JSON/TCP port, each ZeroMQ peer (routing id) being a client of its
//! own; a PUB socket publishes the state every cycle (topic `state`) and every spontaneous
//! error (topic `error`). Every key is optional; the defaults are the documented ones below.

use super::super::{ConfigError, invalid};
use serde::Deserialize;

/// Default endpoint of the command (ROUTER) socket.
pub const DEFAULT_ROUTER: &str = "tcp://127.0.0.1:18012";
/// Default endpoint of the publication (PUB) socket.
pub const DEFAULT_PUBLISH: &str = "tcp://127.0.0.1:18013";
/// Most ZeroMQ peers the gateway may be configured to serve at once.
pub const MAX_PEERS_LIMIT: usize = 4096;

/// `[gateway.zmq]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ZmqConfig {
    /// Serve the ZeroMQ interface (default false; the launcher's `--zmq` switches it on).
    pub enabled: bool,
    /// Endpoint the ROUTER socket binds (default `tcp://127.0.0.1:18012`).
    pub router: String,
    /// Endpoint the PUB socket binds (default `tcp://127.0.0.1:18013`).
    pub publish: String,
    /// Most ZeroMQ peers (routing ids) served at once (default 64); a request from one more
    /// gets an ERROR result.
    pub max_peers: usize,
}

impl Default for ZmqConfig {
    fn default() -> Self {
        Self {
            enabled: false,
            router: DEFAULT_ROUTER.to_string(),
            publish: DEFAULT_PUBLISH.to_string(),
            max_peers: 64,
        }
    }
}

/// Whether `e` looks like a ZeroMQ endpoint this interface can bind: `tcp://HOST:PORT` (PORT
/// may be `*`: any free port) or `ipc://PATH`.
fn endpoint_ok(e: &str) -> bool {
    if let Some(rest) = e.strip_prefix("tcp://") {
        match rest.rsplit_once(':') {
            Some((host, port)) => !host.is_empty() && (port == "*" || port.parse::<u16>().is_ok()),
            None => false,
        }
    } else if let Some(path) = e.strip_prefix("ipc://") {
        !path.is_empty()
    } else {
        false
    }
}

impl ZmqConfig {
    /// Check every key; the first problem found names its key, value and what is allowed.
    pub fn validate(&self) -> Result<(), ConfigError> {
        const P: &str = "gateway.zmq";
        for (key, e) in [("router", &self.router), ("publish", &self.publish)] {
            if !endpoint_ok(e) {
                return Err(invalid(
                    format!("{P}.{key}"),
                    format!("{e:?}"),
                    "an endpoint tcp://HOST:PORT (PORT * for any free port) or ipc://PATH",
                ));
            }
        }
        // The same endpoint twice cannot be bound; two `*` ports are two free ports.
        if self.router == self.publish && !self.router.ends_with(":*") {
            return Err(invalid(
                format!("{P}.publish"),
                format!("{:?}", self.publish),
                "an endpoint other than gateway.zmq.router",
            ));
        }
        if !(1..=MAX_PEERS_LIMIT).contains(&self.max_peers) {
            return Err(invalid(
                format!("{P}.max_peers"),
                self.max_peers,
                format!("1 to {MAX_PEERS_LIMIT}"),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
