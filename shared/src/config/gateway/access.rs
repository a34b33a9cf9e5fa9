//! `[gateway.access]`: from where motion commands are accepted, and the shared secret a
//! connection presents before it may take control. Read and checked at start; the gateway
//! applies it (the real-time core knows nothing of networks or secrets).

use super::super::{ConfigError, invalid};
use core::fmt;
use serde::Deserialize;
use std::net::IpAddr;

/// `[gateway.access]`. The defaults keep the manual's behaviour: motion from anywhere, no
/// secret.
///
/// ```toml
/// [gateway.access]
/// motion_networks = ["10.17.0.0/16", "127.0.0.0/8", "::1/128"]
/// secret_sha256_file = "/etc/mcm/secret.sha256"
/// ```
#[derive(Debug, Clone, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AccessConfig {
    /// Networks (CIDR, IPv4 or IPv6) from which motion commands and `take_control` are
    /// accepted; absent: every network. Clients elsewhere may still read state and `hold`.
    #[serde(default)]
    pub motion_networks: Option<Vec<String>>,
    /// A file holding the SHA-256 of the shared secret as 64 hex digits (what `sha256sum`
    /// prints); when set, a connection must `authenticate` before it may take control.
    #[serde(default)]
    pub secret_sha256_file: Option<String>,
}

impl AccessConfig {
    /// Check every value; the first problem names its key.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.networks().map(|_| ())?;
        if let Some(f) = &self.secret_sha256_file
            && f.trim().is_empty()
        {
            return Err(invalid(
                "gateway.access.secret_sha256_file",
                "\"\"",
                "the path of a file holding the secret's SHA-256 in hex (leave the key out for no secret)",
            ));
        }
        Ok(())
    }

    /// The networks motion is accepted from; `None`: every network.
    pub fn networks(&self) -> Result<Option<Vec<Cidr>>, ConfigError> {
        let Some(list) = &self.motion_networks else {
            return Ok(None);
        };
        list.iter()
            .enumerate()
            .map(|(i, s)| {
                Cidr::parse(s).map_err(|why| {
                    invalid(
                        format!("gateway.access.motion_networks[{i}]"),
                        format!("{s:?}"),
                        format!(
                            "a network as ADDRESS/PREFIX, e.g. \"10.17.0.0/16\" or \"fd00::/8\" ({why})"
                        ),
                    )
                })
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }
}

/// A network: an address and a prefix length (`10.17.0.0/16`, `fd00::/8`). A bare address is
/// the network of that one address.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cidr {
    addr: IpAddr,
    prefix: u8,
}

impl Cidr {
    /// Parse `ADDRESS/PREFIX` or a bare address; says what is wrong otherwise.
    pub fn parse(s: &str) -> Result<Cidr, String> {
        let (a, p) = match s.trim().split_once('/') {
            Some((a, p)) => (a, Some(p)),
            None => (s.trim(), None),
        };
        let addr: IpAddr = a
            .parse()
            .map_err(|_| format!("{a:?} is not an IPv4 or IPv6 address"))?;
        let max = if addr.is_ipv4() { 32 } else { 128 };
        let prefix = match p {
            None => max,
            Some(p) => p
                .parse::<u8>()
                .ok()
                .filter(|n| *n <= max)
                .ok_or_else(|| format!("prefix {p:?} is not a number from 0 to {max}"))?,
        };
        Ok(Cidr { addr, prefix })
    }

    /// Whether `ip` is in this network. An IPv4 address seen as IPv6 (`::ffff:a.b.c.d`, what
    /// a listener on `::` reports) counts as the IPv4 address.
    pub fn contains(&self, ip: IpAddr) -> bool {
        match (self.addr, ip.to_canonical()) {
            (IpAddr::V4(net), IpAddr::V4(ip)) => {
                let mask = u32::MAX
                    .checked_shl(32 - u32::from(self.prefix))
                    .unwrap_or(0);
                u32::from(net) & mask == u32::from(ip) & mask
            }
            (IpAddr::V6(net), IpAddr::V6(ip)) => {
                let mask = u128::MAX
                    .checked_shl(128 - u32::from(self.prefix))
                    .unwrap_or(0);
                u128::from(net) & mask == u128::from(ip) & mask
            }
            _ => false,
        }
    }
}

impl fmt::Display for Cidr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.addr, self.prefix)
    }
}

#[cfg(test)]
mod tests;
