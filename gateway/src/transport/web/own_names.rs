//! The robot's own names: the pendant answers a request only when its `Host` is one of them.
//!
//! A page from another site may make the operator's browser send requests to the pendant; the
//! browser then names that site in `Origin` and the robot in `Host`, and the WebSocket's origin
//! check ([`super::http::same_origin`]) refuses it. After DNS rebinding (the other site's name
//! now resolves to the robot) the browser names the other site in both, and only `Host` tells:
//! it is not a name of the robot. So every route (the page, its files, `/api/*`, `/ws`) is
//! refused with 421 Misdirected Request unless `Host` is `localhost`, a loopback address, the
//! address the port is bound to, an address of this machine's interfaces, or a name of
//! `[gateway.web] allowed_hosts`, with or without a port. A request without `Host` is refused
//! the same way.

use axum::http::{HeaderMap, Uri, header};
use mcm_shared::config::HostName;
use std::net::IpAddr;

/// Why a request is not for the pendant.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refusal {
    /// The request has no `Host` (HTTP/1.0).
    NoHost,
    /// `Host` (or the request target's authority) cannot be read as a host.
    Unreadable { value: String, why: String },
    /// `Host` names another host.
    Foreign(String),
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        const ALLOWED: &str = "the pendant answers only for the robot's own names: localhost, \
             its loopback and network addresses, and the names of [gateway.web] allowed_hosts";
        match self {
            Refusal::NoHost => write!(f, "the request has no Host header; {ALLOWED}"),
            Refusal::Unreadable { value, why } => {
                write!(f, "Host {value:?} is not a host ({why}); {ALLOWED}")
            }
            Refusal::Foreign(host) => write!(
                f,
                "Host {host:?} is not a name of this robot; {ALLOWED} \
                 (add the name there if the robot is reached by it)"
            ),
        }
    }
}

/// The names a request may address the pendant by.
pub struct OwnNames {
    configured: Vec<HostName>,
    bound: IpAddr,
}

impl OwnNames {
    /// The names of `[gateway.web] allowed_hosts` and the address the port is bound to.
    pub fn new(configured: Vec<HostName>, bound: IpAddr) -> OwnNames {
        OwnNames { configured, bound }
    }

    /// Whether a request with these `headers` and target `uri` is for the pendant.
    pub fn check(&self, headers: &HeaderMap, uri: &Uri) -> Result<(), Refusal> {
        let Some(host) = headers.get(header::HOST) else {
            return Err(Refusal::NoHost);
        };
        let host = String::from_utf8_lossy(host.as_bytes());
        self.check_one(&host)?;
        // A request in absolute form (`GET http://HOST/ HTTP/1.1`) names its host there too.
        match uri.authority() {
            Some(a) => self.check_one(a.as_str()),
            None => Ok(()),
        }
    }

    fn check_one(&self, authority: &str) -> Result<(), Refusal> {
        let host = HostName::from_authority(authority).map_err(|why| Refusal::Unreadable {
            value: authority.to_string(),
            why,
        })?;
        if self.is_own(&host) {
            Ok(())
        } else {
            Err(Refusal::Foreign(authority.to_string()))
        }
    }

    /// Whether `host` is one of the robot's names. The machine's addresses are read when asked
    /// (they change with the network); a DNS name never needs them.
    pub fn is_own(&self, host: &HostName) -> bool {
        if host.is_loopback() || self.configured.contains(host) {
            return true;
        }
        match host {
            HostName::Name(_) => false,
            HostName::Addr(a) => {
                let a = a.to_canonical();
                (a == self.bound.to_canonical() && !a.is_unspecified())
                    || local_addresses().contains(&a)
            }
        }
    }
}

/// The addresses of this machine's network interfaces (none when they cannot be read).
pub fn local_addresses() -> Vec<IpAddr> {
    let mut list: *mut libc::ifaddrs = std::ptr::null_mut();
    // SAFETY: getifaddrs writes a list it allocated to `list`, freed below with freeifaddrs.
    if unsafe { libc::getifaddrs(&mut list) } != 0 {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut cur = list;
    while !cur.is_null() {
        // SAFETY: `cur` is a node of the list getifaddrs returned, not yet freed.
        let ifa = unsafe { &*cur };
        if !ifa.ifa_addr.is_null() {
            // SAFETY: `ifa_addr` points to a sockaddr whose family says its real type, and
            // sockaddr_in / sockaddr_in6 are what AF_INET / AF_INET6 address.
            let addr = unsafe {
                match i32::from((*ifa.ifa_addr).sa_family) {
                    libc::AF_INET => {
                        let sin = &*(ifa.ifa_addr as *const libc::sockaddr_in);
                        Some(IpAddr::from(
                            u32::from_be(sin.sin_addr.s_addr).to_be_bytes(),
                        ))
                    }
                    libc::AF_INET6 => {
                        let sin6 = &*(ifa.ifa_addr as *const libc::sockaddr_in6);
                        Some(IpAddr::from(sin6.sin6_addr.s6_addr))
                    }
                    _ => None,
                }
            };
            out.extend(addr);
        }
        cur = ifa.ifa_next;
    }
    // SAFETY: `list` is the list getifaddrs returned; nothing of it is used after this.
    unsafe { libc::freeifaddrs(list) };
    out
}

#[cfg(test)]
mod tests;
