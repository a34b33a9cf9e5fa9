//! Splitting the JSON byte stream of one connection into commands.
//!
//! The transport rules (docs/protocol.md): one JSON object per command, terminated by `\n`
//! (`\r\n` accepted). A complete object that is not yet followed by a newline is taken as soon
//! as it is complete (the manual's own Python example sends none). Whitespace between objects
//! is ignored. A line that does not hold a JSON object, or holds non-ASCII bytes, becomes one
//! [`Frame::Invalid`] and decoding resumes after that line. The limit is exact: an object (from
//! `{` to its `}`), or a line that is not one (without its line end), of [`MAX_COMMAND_BYTES`]
//! bytes is taken; one byte more is [`Frame::Oversize`] as soon as that byte arrives; the
//! connection is then closed, so the memory a connection holds stays bounded. A first line
//! (blank lines aside) that is an HTTP request line or header is [`Frame::Http`]
//! ([`crate::transport::http_line`]): the connection is closed without executing anything.

use crate::transport::http_line::{self, HttpLine};
use mcm_shared::protocol::json::json_kind;

/// Longest command accepted (64 KiB): the contract's limit.
pub use mcm_shared::protocol::MAX_COMMAND_BYTES;

/// One unit of input.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Frame {
    /// A syntactically complete JSON object (ASCII), still to be parsed.
    Object(String),
    /// A line that is not a JSON object; `reason` says why.
    Invalid { reason: String },
    /// A command longer than [`MAX_COMMAND_BYTES`].
    Oversize,
    /// The connection's first line is HTTP, not a command.
    Http(HttpLine),
}

/// Incremental decoder. Feed bytes with [`Decoder::extend`], take frames with
/// [`Decoder::next_frame`].
#[derive(Debug, Default)]
pub struct Decoder {
    buf: Vec<u8>,
    /// Scan position inside the current frame (bytes before it are already classified).
    scan: usize,
    depth: usize,
    in_string: bool,
    escape: bool,
    non_ascii: Option<(usize, u8)>,
    /// Discarding the rest of a bad line up to its newline.
    skipping_line: bool,
    /// A frame was taken already: the next line is not the connection's first.
    framed: bool,
}

fn excerpt(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes);
    let text = text.trim();
    if text.chars().count() > 40 {
        format!("{}...", text.chars().take(40).collect::<String>())
    } else {
        text.to_string()
    }
}

impl Decoder {
    pub fn new() -> Self {
        Self::default()
    }

    /// Append received bytes.
    pub fn extend(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
    }

    /// Bytes held that do not form a frame yet.
    pub fn buffered(&self) -> usize {
        self.buf.len()
    }

    fn reset_scan(&mut self, consumed: usize) {
        self.buf.drain(..consumed);
        self.scan = 0;
        self.depth = 0;
        self.in_string = false;
        self.escape = false;
        self.non_ascii = None;
    }

    /// The next complete frame, or `None` if more bytes are needed.
    pub fn next_frame(&mut self) -> Option<Frame> {
        let frame = self.take_frame();
        self.framed |= frame.is_some();
        frame
    }

    fn take_frame(&mut self) -> Option<Frame> {
        if self.skipping_line {
            match self.buf.iter().position(|&b| b == b'\n') {
                Some(nl) => {
                    self.reset_scan(nl + 1);
                    self.skipping_line = false;
                }
                None => {
                    self.buf.clear();
                    return None;
                }
            }
        }
        // Skip whitespace between frames.
        if self.scan == 0 {
            let ws = self
                .buf
                .iter()
                .take_while(|b| matches!(b, b' ' | b'\t' | b'\r' | b'\n'))
                .count();
            if ws > 0 {
                self.reset_scan(ws);
            }
            if self.buf.is_empty() {
                return None;
            }
        }
        if self.buf[0] != b'{' {
            // Not an object: the frame is the whole line, at most MAX_COMMAND_BYTES before
            // its newline.
            let window = &self.buf[..self.buf.len().min(MAX_COMMAND_BYTES + 1)];
            return match window.iter().position(|&b| b == b'\n') {
                Some(nl) => {
                    let line = &self.buf[..nl];
                    let frame = match http_line::classify(line) {
                        Some(kind) if !self.framed => Frame::Http(kind),
                        _ => Frame::Invalid {
                            reason: describe_non_object(line),
                        },
                    };
                    self.reset_scan(nl + 1);
                    Some(frame)
                }
                None if window.len() > MAX_COMMAND_BYTES => {
                    self.reset_scan(MAX_COMMAND_BYTES + 1);
                    self.skipping_line = true;
                    Some(Frame::Oversize)
                }
                None => None,
            };
        }
        self.scan_object()
    }

    /// Continue scanning an object that starts at `buf[0]`.
    fn scan_object(&mut self) -> Option<Frame> {
        while self.scan < self.buf.len() {
            let i = self.scan;
            let b = self.buf[i];
            if i == MAX_COMMAND_BYTES && b != b'\n' {
                // The object would be longer than the limit (a newline here still ends a line
                // of exactly the limit, reported as incomplete below).
                self.reset_scan(i);
                self.skipping_line = true;
                return Some(Frame::Oversize);
            }
            self.scan += 1;
            if b >= 0x80 && self.non_ascii.is_none() {
                self.non_ascii = Some((i, b));
            }
            if b == b'\n' {
                // A newline ends the line: the object is incomplete.
                let text = excerpt(&self.buf[..i]);
                self.reset_scan(i + 1);
                return Some(Frame::Invalid {
                    reason: format!(
                        "incomplete JSON object at end of line: `{text}` (a command must be one JSON object on one line)"
                    ),
                });
            }
            if self.in_string {
                if self.escape {
                    self.escape = false;
                } else if b == b'\\' {
                    self.escape = true;
                } else if b == b'"' {
                    self.in_string = false;
                }
                continue;
            }
            match b {
                b'"' => self.in_string = true,
                b'{' | b'[' => self.depth += 1,
                b'}' | b']' => {
                    self.depth = self.depth.saturating_sub(1);
                    if self.depth == 0 {
                        let end = i + 1;
                        let frame = match self.non_ascii {
                            Some((pos, byte)) => Frame::Invalid {
                                reason: format!(
                                    "non-ASCII byte 0x{byte:02X} at position {pos}; commands must be ASCII (use \\u escapes in strings)"
                                ),
                            },
                            None => Frame::Object(
                                String::from_utf8(self.buf[..end].to_vec()).expect("checked ASCII"),
                            ),
                        };
                        self.reset_scan(end);
                        return Some(frame);
                    }
                }
                _ => {}
            }
        }
        None
    }
}

fn describe_non_object(line: &[u8]) -> String {
    if let Some((pos, b)) = line.iter().enumerate().find(|(_, b)| **b >= 0x80) {
        return format!(
            "non-ASCII byte 0x{b:02X} at position {pos}; commands must be ASCII JSON objects"
        );
    }
    match serde_json::from_slice::<serde_json::Value>(line) {
        Ok(v) => format!(
            "expected a JSON object like {{\"command\":\"status\"}}, got a JSON {}: `{}`",
            json_kind(&v),
            excerpt(line)
        ),
        Err(e) => format!("invalid JSON ({e}): `{}`", excerpt(line)),
    }
}

#[cfg(test)]
mod tests;
