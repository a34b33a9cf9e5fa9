//! The ready lines: the one line on stdout by which each MCM program says it serves, and where.
//! `mcm-rt` prints [`RtReady`], `mcm-gateway` prints [`GatewayReady`], and the `mcm` launcher,
//! which reads both, prints [`McmReady`] for people and for the programs that start it (tests,
//! benchmarks, `mcm_client::launch`). Each has one `Display` (what is printed) and one
//! `FromStr` (what a reader accepts); the fields are `key=value` words, so a reader finds them
//! by name, ignores keys it does not know (a newer program may add some), and refuses a line
//! that lacks one or holds a value of the wrong form. A reader reads only the fields: the
//! launcher's words for people may change without breaking one.
//!
//! ```
//! use mcm_shared::ready::{GatewayReady, ReadyLine};
//! let line = "mcm-gateway ready json=127.0.0.1:18010 hmi=127.0.0.1:18011";
//! let ready: GatewayReady = line.parse()?;
//! assert_eq!(ready.json.port(), 18010);
//! assert!(line.starts_with(GatewayReady::PREFIX));
//! assert_eq!(ready.to_string(), line);
//! # Ok::<(), mcm_shared::ready::ReadyError>(())
//! ```

use crate::config::BusBackend;
use std::fmt;
use std::net::SocketAddr;
use std::str::FromStr;

/// A program's ready line: what it starts with, and its one `Display` and `FromStr`.
pub trait ReadyLine: fmt::Display + FromStr<Err = ReadyError> {
    /// The words the line starts with.
    const PREFIX: &'static str;
}

/// A line that is not the ready line it should be.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReadyError {
    #[error("not a ready line (`{prefix}` expected at its start): {line:?}")]
    NotReady { prefix: &'static str, line: String },
    #[error("the ready line has no `{key}=`: {line:?}")]
    Missing { key: &'static str, line: String },
    #[error("the ready line's `{key}={value}` is not {expected}: {line:?}")]
    Invalid {
        key: &'static str,
        value: String,
        expected: &'static str,
        line: String,
    },
}

/// `mcm-rt ready instance=NAME bus=sim|socketcan`: the core publishes its state.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RtReady {
    pub instance: String,
    pub bus: BusBackend,
}

/// `mcm-gateway ready json=ADDR hmi=ADDR [web=ADDR] [zmq_router=ENDPOINT zmq_publish=ENDPOINT]`:
/// the gateway listens, on these addresses as bound (port 0 asked for any free port).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GatewayReady {
    pub json: SocketAddr,
    pub hmi: SocketAddr,
    /// The browser pendant's HTTP port, when `[gateway.web]` is enabled.
    pub web: Option<SocketAddr>,
    /// The ZeroMQ endpoints as bound, when the ZeroMQ interface is on.
    pub zmq: Option<ZmqEndpoints>,
}

/// `mcm-ros2 ready node=NAME domain=N instance=NAME`: the ROS 2 node (`mcm-ros2`) serves its
/// topics, services and action as node `NAME` (fully qualified, e.g. `/left/mcm`) on DDS
/// domain `N`, for the MCM instance `instance`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ros2Ready {
    pub node: String,
    pub domain: u16,
    pub instance: String,
}

/// `mcm-virtual-arm ready interface=NAME control=ADDRESS`: the virtual P-Rob2 (`mcm-virtual-arm`)
/// answers as the arm's six drives on the CAN interface `NAME`, and takes fault injections and
/// gives its ground truth (the contract's `sim` command) on the TCP address `control`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VirtualArmReady {
    pub interface: String,
    pub control: SocketAddr,
}

/// Where the gateway's ZeroMQ sockets are bound.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ZmqEndpoints {
    /// The ROUTER socket (commands), e.g. `tcp://127.0.0.1:18012`.
    pub router: String,
    /// The PUB socket (state and errors).
    pub publish: String,
}

/// The launcher's line: words for people, then the fields in brackets, e.g.
/// `MCM ready (simulated P-Rob2, instance default): JSON on 0.0.0.0:18010, telnet HMI on
/// 0.0.0.0:18011; Ctrl-C stops. [instance=default robot=simulated%20P-Rob2
/// json=0.0.0.0:18010 hmi=0.0.0.0:18011 rt_pid=4242 gateway_pid=4243]`. In the `robot` field
/// a space (any white space), `%`, `[` and `]` are written as `%` and two hex digits per byte.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct McmReady {
    /// The robot in words, e.g. "simulated P-Rob2" (written with every control character as
    /// `?`, so that a robot name from the configuration cannot drive the terminal).
    pub robot: String,
    pub instance: String,
    /// Where the gateway serves.
    pub gateway: GatewayReady,
    pub rt_pid: u32,
    pub gateway_pid: u32,
}

impl ReadyLine for RtReady {
    const PREFIX: &'static str = "mcm-rt ready";
}

impl ReadyLine for GatewayReady {
    const PREFIX: &'static str = "mcm-gateway ready";
}

impl ReadyLine for Ros2Ready {
    const PREFIX: &'static str = "mcm-ros2 ready";
}

impl ReadyLine for VirtualArmReady {
    const PREFIX: &'static str = "mcm-virtual-arm ready";
}

impl fmt::Display for VirtualArmReady {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (prefix, interface, control) = (Self::PREFIX, &self.interface, self.control);
        write!(f, "{prefix} interface={interface} control={control}")
    }
}

impl FromStr for VirtualArmReady {
    type Err = ReadyError;

    fn from_str(line: &str) -> Result<Self, ReadyError> {
        let fields = Fields::new(line, after_prefix(line, Self::PREFIX)?);
        Ok(VirtualArmReady {
            interface: fields.text("interface")?.to_string(),
            control: fields.parsed("control", "a socket address, e.g. 127.0.0.1:18020")?,
        })
    }
}

impl fmt::Display for Ros2Ready {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (prefix, node, domain, instance) =
            (Self::PREFIX, &self.node, self.domain, &self.instance);
        write!(
            f,
            "{prefix} node={node} domain={domain} instance={instance}"
        )
    }
}

impl FromStr for Ros2Ready {
    type Err = ReadyError;

    fn from_str(line: &str) -> Result<Self, ReadyError> {
        let fields = Fields::new(line, after_prefix(line, Self::PREFIX)?);
        const DOMAIN: &str = "a DDS domain id (0 to 232)";
        let domain: u16 = fields.parsed("domain", DOMAIN)?;
        if domain > 232 {
            return Err(ReadyError::Invalid {
                key: "domain",
                value: domain.to_string(),
                expected: DOMAIN,
                line: line.to_string(),
            });
        }
        Ok(Ros2Ready {
            node: fields.text("node")?.to_string(),
            domain,
            instance: fields.text("instance")?.to_string(),
        })
    }
}

impl ReadyLine for McmReady {
    const PREFIX: &'static str = "MCM ready";
}

impl fmt::Display for RtReady {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (prefix, instance, bus) = (Self::PREFIX, &self.instance, self.bus);
        write!(f, "{prefix} instance={instance} bus={bus}")
    }
}

/// `text` with every control character as `?`, so that it cannot drive a terminal.
fn without_controls(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect()
}

/// Whether `c` is written as `%XX` bytes in a field.
fn escaped(c: char) -> bool {
    c.is_whitespace() || c.is_control() || matches!(c, '%' | '[' | ']')
}

/// `text` as one field value: no white space, no brackets.
fn field_value(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if escaped(c) {
            let mut buf = [0u8; 4];
            for b in c.encode_utf8(&mut buf).bytes() {
                out.push_str(&format!("%{b:02X}"));
            }
        } else {
            out.push(c);
        }
    }
    out
}

/// The text a field value stands for (`None`: a `%` without two hex digits, or bytes that are
/// not UTF-8).
fn field_text(value: &str) -> Option<String> {
    let mut bytes = Vec::with_capacity(value.len());
    let mut rest = value.as_bytes();
    while let Some((&b, tail)) = rest.split_first() {
        if b == b'%' {
            let hex = std::str::from_utf8(tail.get(..2)?).ok()?;
            bytes.push(u8::from_str_radix(hex, 16).ok()?);
            rest = &tail[2..];
        } else {
            bytes.push(b);
            rest = tail;
        }
    }
    String::from_utf8(bytes).ok()
}

impl GatewayReady {
    /// The fields of the line, as `key=value` words separated by spaces.
    fn fields(&self) -> String {
        let mut s = format!("json={} hmi={}", self.json, self.hmi);
        if let Some(w) = &self.web {
            s.push_str(&format!(" web={w}"));
        }
        if let Some(z) = &self.zmq {
            s.push_str(&format!(
                " zmq_router={} zmq_publish={}",
                z.router, z.publish
            ));
        }
        s
    }
}

impl fmt::Display for GatewayReady {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}", Self::PREFIX, self.fields())
    }
}

impl McmReady {
    /// What follows the robot's words, up to the bracket.
    fn words_after_robot(&self) -> String {
        let g = &self.gateway;
        let zmq = g
            .zmq
            .as_ref()
            .map(|z| {
                format!(
                    ", ZeroMQ commands on {} and state on {}",
                    z.router, z.publish
                )
            })
            .unwrap_or_default();
        let web = g
            .web
            .map(|w| format!(", browser pendant on http://{w}/"))
            .unwrap_or_default();
        format!(
            ", instance {}): JSON on {}, telnet HMI on {}{web}{zmq}; Ctrl-C stops.",
            self.instance, g.json, g.hmi
        )
    }
}

impl fmt::Display for McmReady {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let robot = without_controls(&self.robot);
        write!(
            f,
            "{} ({robot}{} [instance={} robot={} {} rt_pid={} gateway_pid={}]",
            Self::PREFIX,
            self.words_after_robot(),
            self.instance,
            field_value(&robot),
            self.gateway.fields(),
            self.rt_pid,
            self.gateway_pid
        )
    }
}

/// The `key=value` words of a line, read by name.
struct Fields<'a> {
    line: &'a str,
    words: Vec<(&'a str, &'a str)>,
}

impl<'a> Fields<'a> {
    fn new(line: &'a str, fields: &'a str) -> Self {
        let words = fields
            .split_whitespace()
            .filter_map(|w| w.split_once('='))
            .collect();
        Self { line, words }
    }

    fn get(&self, key: &'static str) -> Option<&'a str> {
        self.words.iter().find(|(k, _)| *k == key).map(|(_, v)| *v)
    }

    fn text(&self, key: &'static str) -> Result<&'a str, ReadyError> {
        self.get(key).ok_or_else(|| ReadyError::Missing {
            key,
            line: self.line.to_string(),
        })
    }

    fn parsed<T: FromStr>(
        &self,
        key: &'static str,
        expected: &'static str,
    ) -> Result<T, ReadyError> {
        let value = self.text(key)?;
        value.parse().map_err(|_| ReadyError::Invalid {
            key,
            value: value.to_string(),
            expected,
            line: self.line.to_string(),
        })
    }

    fn gateway(&self) -> Result<GatewayReady, ReadyError> {
        let zmq = match (self.get("zmq_router"), self.get("zmq_publish")) {
            (None, None) => None,
            _ => Some(ZmqEndpoints {
                router: self.text("zmq_router")?.to_string(),
                publish: self.text("zmq_publish")?.to_string(),
            }),
        };
        Ok(GatewayReady {
            json: self.parsed("json", "an address and port")?,
            hmi: self.parsed("hmi", "an address and port")?,
            web: match self.get("web") {
                None => None,
                Some(_) => Some(self.parsed("web", "an address and port")?),
            },
            zmq,
        })
    }
}

/// `line` after `prefix` and a space.
fn after_prefix<'a>(line: &'a str, prefix: &'static str) -> Result<&'a str, ReadyError> {
    line.strip_prefix(prefix)
        .and_then(|r| r.strip_prefix(' '))
        .ok_or_else(|| ReadyError::NotReady {
            prefix,
            line: line.to_string(),
        })
}

impl FromStr for RtReady {
    type Err = ReadyError;

    fn from_str(line: &str) -> Result<Self, ReadyError> {
        let fields = Fields::new(line, after_prefix(line, Self::PREFIX)?);
        Ok(RtReady {
            instance: fields.text("instance")?.to_string(),
            bus: fields.parsed("bus", BusBackend::WORDS)?,
        })
    }
}

impl FromStr for GatewayReady {
    type Err = ReadyError;

    fn from_str(line: &str) -> Result<Self, ReadyError> {
        Fields::new(line, after_prefix(line, Self::PREFIX)?).gateway()
    }
}

impl FromStr for McmReady {
    type Err = ReadyError;

    fn from_str(line: &str) -> Result<Self, ReadyError> {
        let rest = after_prefix(line, Self::PREFIX)?;
        // The fields are the last bracket: the robot's words before it may hold anything
        // but a control character, its field holds no bracket.
        let start = rest.rfind("[instance=").ok_or(ReadyError::Missing {
            key: "instance",
            line: line.to_string(),
        })?;
        let bracket = &rest[start..];
        let fields = Fields::new(line, bracket.trim_start_matches('[').trim_end_matches(']'));
        let robot = fields.text("robot")?;
        Ok(McmReady {
            robot: field_text(robot).ok_or_else(|| ReadyError::Invalid {
                key: "robot",
                value: robot.to_string(),
                expected: "text with `%` followed by two hex digits of UTF-8",
                line: line.to_string(),
            })?,
            instance: fields.text("instance")?.to_string(),
            gateway: fields.gateway()?,
            rt_pid: fields.parsed("rt_pid", "a process id")?,
            gateway_pid: fields.parsed("gateway_pid", "a process id")?,
        })
    }
}

#[cfg(test)]
mod tests;
