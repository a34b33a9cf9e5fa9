//! Recognising HTTP sent to the line ports (JSON and telnet HMI).
//!
//! Any web page can make a browser send a request to the robot's JSON or telnet port (`fetch`
//! with `mode: "no-cors"` needs no permission): its request line and headers are not commands,
//! but the lines of its body would be. Both ports therefore close, without executing anything,
//! a connection whose first line (blank lines aside) is an HTTP request line or header
//! ([`classify`]); a browser always begins with one. A valid command never looks like either:
//! a JSON command starts with `{`, which is not part of an HTTP token, and no HMI command word
//! contains `:` or is followed by a request target and an `HTTP/x.y` version.

use std::net::SocketAddr;

/// Which kind of HTTP line a line is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HttpLine {
    /// `METHOD SP target SP HTTP/x.y`, e.g. `POST / HTTP/1.1`.
    Request,
    /// `Name: value`, e.g. `Host: robot:18010`.
    Header,
}

impl HttpLine {
    /// The kind in words, for the log.
    pub fn words(self) -> &'static str {
        match self {
            HttpLine::Request => "an HTTP request line",
            HttpLine::Header => "an HTTP header",
        }
    }
}

/// Whether `line` (without its line end; a trailing `\r` and surrounding blanks are ignored) is
/// an HTTP request line or header line.
pub fn classify(line: &[u8]) -> Option<HttpLine> {
    let line = line.trim_ascii();
    if is_request_line(line) {
        Some(HttpLine::Request)
    } else if is_header(line) {
        Some(HttpLine::Header)
    } else {
        None
    }
}

/// Log, once for the connection that is being closed, that `peer`, a client of the channel
/// `who` (e.g. "JSON client"), sent HTTP.
pub fn log_refused(who: &str, peer: SocketAddr, kind: HttpLine) {
    eprintln!(
        "mcm-gateway: {who} {peer}: its first line is {}, not a command (a web page can make a \
         browser send one); closed without executing anything",
        kind.words()
    );
}

/// An HTTP token character (RFC 9110 `tchar`): the characters of a method or header name.
fn is_tchar(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b"!#$%&'*+-.^_`|~".contains(&b)
}

fn is_token(s: &[u8]) -> bool {
    !s.is_empty() && s.iter().all(|&b| is_tchar(b))
}

/// `METHOD SP target SP HTTP/DIGIT[.DIGIT]`: a token, a target without blanks or control
/// characters, and the version.
fn is_request_line(line: &[u8]) -> bool {
    let mut parts = line.split(|&b| b == b' ');
    let (Some(method), Some(target), Some(version), None) =
        (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return false;
    };
    is_token(method)
        && !target.is_empty()
        && target.iter().all(|b| b.is_ascii_graphic() || *b >= 0x80)
        && is_version(version)
}

/// `HTTP/` then digits, optionally `.` and digits (`HTTP/1.1`, `HTTP/1.0`, `HTTP/2`).
fn is_version(v: &[u8]) -> bool {
    let Some(number) = v.strip_prefix(b"HTTP/") else {
        return false;
    };
    let (major, minor) = match number.iter().position(|&b| b == b'.') {
        Some(dot) => (&number[..dot], Some(&number[dot + 1..])),
        None => (number, None),
    };
    let digits = |d: &[u8]| !d.is_empty() && d.iter().all(u8::is_ascii_digit);
    digits(major) && minor.is_none_or(digits)
}

/// `Name:` then anything: a token right before the first `:`.
fn is_header(line: &[u8]) -> bool {
    line.iter()
        .position(|&b| b == b':')
        .is_some_and(|colon| is_token(&line[..colon]))
}

#[cfg(test)]
mod tests;
