//! One ZeroMQ request message as one JSON command, and the envelope of the reply. Runs in the
//! gateway's ZeroMQ thread and async tasks, not in the cycle.
//!
//! A request is one message whose last frame holds exactly one JSON command (no line end
//! needed; the same rules as a line of the JSON/TCP port otherwise: an object, ASCII, at most
//! [`MAX_COMMAND_BYTES`]). The frames before it are the envelope the ROUTER socket received
//! (the peer's routing id, then the empty delimiter a REQ socket adds, if any); the reply goes
//! back with the same envelope, so REQ and DEALER peers both work. Whatever the bytes, the
//! decoder gives one [`Frame`]: a command to run or the reason to refuse it, never a panic.

use crate::transport::json::framing::{Decoder, Frame, MAX_COMMAND_BYTES};

/// A request's frames split into the envelope (routing id and delimiters) and the body.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Request {
    /// The frames to send back before the reply: the routing id first.
    pub envelope: Vec<Vec<u8>>,
    /// The command's bytes.
    pub body: Vec<u8>,
}

impl Request {
    /// Split the frames of one ROUTER message; `None` when it has no body (only a routing id:
    /// nothing to answer).
    pub fn from_frames(mut frames: Vec<Vec<u8>>) -> Option<Request> {
        if frames.len() < 2 {
            return None;
        }
        let body = frames.pop()?;
        Some(Request {
            envelope: frames,
            body,
        })
    }

    /// The frames of the reply `json` to this request.
    pub fn reply(&self, json: String) -> Vec<Vec<u8>> {
        let mut frames = self.envelope.clone();
        frames.push(json.into_bytes());
        frames
    }
}

/// What one message's body asks for: exactly one [`Frame`].
pub fn frame(body: &[u8]) -> Frame {
    if body.len() > MAX_COMMAND_BYTES {
        return Frame::Invalid {
            reason: format!(
                "a message of {} bytes is longer than the limit of {MAX_COMMAND_BYTES} bytes; \
                 nothing was done",
                body.len()
            ),
        };
    }
    let mut d = Decoder::new();
    d.extend(body);
    d.extend(b"\n");
    let first = d.next_frame();
    let more = d.next_frame().is_some() || d.buffered() > 0;
    match first {
        None if d.buffered() > 0 => Frame::Invalid {
            reason: "the message is not a complete JSON object (send one command per message, \
                     e.g. {\"command\":\"status\"}); nothing was done"
                .to_string(),
        },
        None => Frame::Invalid {
            reason: "an empty message: send one JSON command per message, e.g. \
                     {\"command\":\"status\"}; nothing was done"
                .to_string(),
        },
        Some(_) if more => Frame::Invalid {
            reason: "a message holds more than one command: send one JSON command per message \
                     (each gets its own reply); nothing was done"
                .to_string(),
        },
        Some(Frame::Oversize) => Frame::Invalid {
            reason: format!(
                "the command is longer than the limit of {MAX_COMMAND_BYTES} bytes; nothing \
                 was done"
            ),
        },
        Some(f) => f,
    }
}

#[cfg(test)]
mod tests;
