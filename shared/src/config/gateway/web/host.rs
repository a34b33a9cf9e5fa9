//! A host as the pendant's names are written: in `[gateway.web] allowed_hosts` (a DNS name or
//! an IP address) and in a request's `Host` header (the same, with an optional port, an IPv6
//! address in brackets). One parser for both, so that a configured name and a request's name
//! compare as equal exactly when they name the same host.

use core::fmt;
use std::net::IpAddr;

/// The longest DNS name (RFC 1035), without its trailing dot.
const MAX_NAME: usize = 253;
/// The longest label of a DNS name.
const MAX_LABEL: usize = 63;

/// A host: a DNS name (lower case, without a trailing dot) or an IP address.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum HostName {
    Name(String),
    Addr(IpAddr),
}

impl HostName {
    /// A host without a port: `robot.example`, `10.17.0.5`, `fd00::5` or `[fd00::5]`; says what
    /// is wrong otherwise.
    pub fn parse(s: &str) -> Result<HostName, String> {
        let s = s.trim();
        let bracketed = s.strip_prefix('[').and_then(|r| r.strip_suffix(']'));
        if let Some(inner) = bracketed {
            return match inner.parse::<IpAddr>() {
                Ok(a @ IpAddr::V6(_)) => Ok(HostName::Addr(a)),
                _ => Err(format!("{inner:?} in brackets is not an IPv6 address")),
            };
        }
        if let Ok(a) = s.parse::<IpAddr>() {
            return Ok(HostName::Addr(a));
        }
        let name = s.strip_suffix('.').unwrap_or(s);
        if name.is_empty() {
            return Err("it is empty".into());
        }
        if name.len() > MAX_NAME {
            return Err(format!("longer than {MAX_NAME} characters"));
        }
        for label in name.split('.') {
            let letters = label
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_');
            if label.is_empty() || label.len() > MAX_LABEL || !letters {
                return Err(format!(
                    "{label:?} is not a DNS label (1..={MAX_LABEL} letters, digits, '-' or '_')"
                ));
            }
        }
        Ok(HostName::Name(name.to_ascii_lowercase()))
    }

    /// The host of an HTTP `Host` header (or a URL's authority): `name`, `name:port`,
    /// `1.2.3.4:port`, `[v6]` or `[v6]:port`; says what is wrong otherwise.
    pub fn from_authority(s: &str) -> Result<HostName, String> {
        let host = if s.starts_with('[') {
            match s.find(']') {
                Some(end) => {
                    port_ok(&s[end + 1..])?;
                    &s[..=end]
                }
                None => return Err(format!("{s:?} opens a bracket it does not close")),
            }
        } else if s.matches(':').count() > 1 {
            return Err(format!("{s:?}: an IPv6 address must be in brackets"));
        } else {
            match s.rsplit_once(':') {
                Some((h, p)) => {
                    port_ok(&format!(":{p}"))?;
                    h
                }
                None => s,
            }
        };
        HostName::parse(host)
    }

    /// Whether this is `localhost` or a loopback address (IPv4 as IPv6 included).
    pub fn is_loopback(&self) -> bool {
        match self {
            HostName::Name(n) => n == "localhost",
            HostName::Addr(a) => a.to_canonical().is_loopback(),
        }
    }
}

/// `rest` after a host is nothing or `:PORT`.
fn port_ok(rest: &str) -> Result<(), String> {
    match rest.strip_prefix(':') {
        None if rest.is_empty() => Ok(()),
        Some(p) if p.parse::<u16>().is_ok() => Ok(()),
        _ => Err(format!("{rest:?} is not a port (:1..65535)")),
    }
}

impl fmt::Display for HostName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HostName::Name(n) => f.write_str(n),
            HostName::Addr(IpAddr::V6(a)) => write!(f, "[{a}]"),
            HostName::Addr(a) => write!(f, "{a}"),
        }
    }
}

#[cfg(test)]
mod tests;
