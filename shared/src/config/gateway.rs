//! The `[gateway]` section: how the gateway limits connections (`[gateway.connections]`),
//! who may move the arm (`[gateway.access]`), its ZeroMQ interface (`[gateway.zmq]`, off by
//! default) and the browser pendant (`[gateway.web]`, on by default). The whole section is
//! optional; its defaults keep the manual's behaviour (any client on the factory network may
//! connect and command).

use super::ConfigError;
use serde::Deserialize;

/// `[gateway]`.
#[derive(Debug, Clone, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GatewayConfig {
    #[serde(default)]
    pub connections: ConnectionLimits,
    #[serde(default)]
    pub access: AccessConfig,
    #[serde(default)]
    pub zmq: ZmqConfig,
    #[serde(default)]
    pub web: WebConfig,
}

mod connections;
pub use connections::ConnectionLimits;

mod access;
pub use access::{AccessConfig, Cidr};

pub mod zmq;
pub use zmq::ZmqConfig;

pub mod web;
pub use web::{HostName, WebConfig};

impl GatewayConfig {
    /// Check every value of the section; the first problem found names its key.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.connections.validate()?;
        self.access.validate()?;
        self.zmq.validate()?;
        self.web.validate()?;
        Ok(())
    }
}
