//! The `[gateway]` section: how the gateway limits connections (`[gateway.connections]`) and
//! who may move the arm (`[gateway.access]`). The whole section is optional; its defaults keep
//! the manual's behaviour (any client on the factory network may connect and command).

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
}

mod connections;
pub use connections::ConnectionLimits;

mod access;
pub use access::{AccessConfig, Cidr};

impl GatewayConfig {
    /// Check every value of the section; the first problem found names its key.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.connections.validate()?;
        self.access.validate()?;
        Ok(())
    }
}
