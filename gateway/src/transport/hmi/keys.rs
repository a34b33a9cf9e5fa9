//! The HMI's one key decoder: turns the data bytes of a session ([`super::telnet::Input::Byte`])
//! into typed bytes and cursor keys, reading every escape sequence to its end. Both the line
//! editor ([`super::editor`]) and the jog screen ([`super::jog`]) read their keys through it,
//! so no byte of an escape sequence ever counts as a typed character or a key of its own. Runs
//! in the gateway's async tasks, not in the real-time cycle.
//!
//! Escape sequences (ECMA-48, 7-bit) are read to their end whatever their length: `ESC [` or
//! `ESC O`, parameter and intermediate bytes (0x20-0x3F), a final byte (0x40-0x7E) is a key
//! ([`Key::Csi`]); `ESC`, intermediate bytes (0x20-0x2F), a final byte (0x30-0x7E), `ESC x`
//! (Alt-x) included, and control strings (`ESC ]`, `ESC P`, `ESC X`, `ESC ^`, `ESC _`) up to BEL
//! or `ESC \` are no keys: they are dropped whole ([`Decoded::dropped`]), as is a key whose
//! parameters are longer than [`MAX_KEY_PARAMS`]. Inside a sequence a control character counts
//! as typed, as it would outside (Ctrl-C still interrupts) and the sequence goes on; DEL is
//! ignored; CAN and SUB cancel the sequence; ESC starts a new one; a byte above 0x7F (outside a
//! control string) ends it and counts as typed. Only the parameters of a key are kept, at most
//! [`MAX_KEY_PARAMS`] bytes, so memory stays bounded whatever a peer sends.

/// Longest parameters of a key kept (`ESC [ 1 ; 5 C` has 3); a sequence with longer ones is
/// read to its end and dropped.
pub const MAX_KEY_PARAMS: usize = 8;

/// CAN and SUB cancel an escape sequence (ECMA-48).
const CANCEL: [u8; 2] = [0x18, 0x1A];

/// The parameter bytes of a CSI or SS3 sequence, as far as a key needs them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Params {
    bytes: [u8; MAX_KEY_PARAMS],
    len: usize,
    /// More than [`MAX_KEY_PARAMS`] came: the sequence is no key.
    long: bool,
}

impl Params {
    fn push(&mut self, b: u8) {
        match self.bytes.get_mut(self.len) {
            Some(slot) => {
                *slot = b;
                self.len += 1;
            }
            None => self.long = true,
        }
    }
}

/// A cursor or editing key: `ESC [ <params> <last>` or `ESC O <last>`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Csi {
    params: Params,
    /// The final byte (`A` for Up, `~` for the keys numbered by their parameter, ...).
    pub last: u8,
}

impl Csi {
    /// The parameters as text (at most [`MAX_KEY_PARAMS`] bytes), e.g. `1;5` or `3`.
    pub fn params(&self) -> &str {
        // Only bytes 0x20-0x3F are pushed: ASCII.
        std::str::from_utf8(&self.params.bytes[..self.params.len]).unwrap_or_default()
    }
}

/// What a byte completed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    /// A byte that is no part of an escape sequence: a character (ASCII, or one byte of a UTF-8
    /// one) or a control character. Never ESC.
    Typed(u8),
    /// A cursor or editing key.
    Csi(Csi),
}

/// What one byte did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Decoded {
    /// An escape sequence ended with this byte without being a key: it was read whole and
    /// dropped (before `key`, if any).
    pub dropped: bool,
    /// The key this byte completed.
    pub key: Option<Key>,
}

impl Decoded {
    const NOTHING: Decoded = Decoded {
        dropped: false,
        key: None,
    };
    const DROPPED: Decoded = Decoded {
        dropped: true,
        key: None,
    };

    fn typed(b: u8) -> Decoded {
        Decoded {
            dropped: false,
            key: Some(Key::Typed(b)),
        }
    }
}

/// Where the decoder is in an escape sequence: what the next byte means.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Esc {
    #[default]
    None,
    /// After ESC.
    Start,
    /// After `ESC [` or `ESC O`, with the parameter and intermediate bytes so far.
    Csi(Params),
    /// After ESC and intermediate bytes (0x20-0x2F), before the final byte.
    Intermediate,
    /// Inside a control string (`ESC ]` ...), up to BEL or `ESC \` (ST).
    String,
    /// ESC inside a control string: `\` ends it (ST); anything else ends it, and the ESC
    /// starts a new sequence.
    StringEnd,
}

/// One session's key decoder. Feed it the data bytes with [`KeyDecoder::byte`]; the other
/// inputs (Enter, Ctrl-C as `IAC IP`, ...) end a sequence under way: [`KeyDecoder::reset`].
#[derive(Debug, Clone, Default)]
pub struct KeyDecoder {
    esc: Esc,
}

impl KeyDecoder {
    /// True inside an escape sequence (its bytes so far are neither typed nor dropped yet).
    pub fn in_sequence(&self) -> bool {
        self.esc != Esc::None
    }

    /// Forget the sequence under way, if any; true when there was one (it is dropped).
    pub fn reset(&mut self) -> bool {
        std::mem::take(&mut self.esc) != Esc::None
    }

    /// Take one data byte.
    pub fn byte(&mut self, b: u8) -> Decoded {
        let (esc, decoded) = match (self.esc, b) {
            (Esc::None, 0x1B) => (Esc::Start, Decoded::NOTHING),
            (Esc::None, b) => (Esc::None, Decoded::typed(b)),
            // In a control string everything but its terminators belongs to it.
            (Esc::String, 0x07) => (Esc::None, Decoded::DROPPED),
            (Esc::String, 0x1B) => (Esc::StringEnd, Decoded::NOTHING),
            (Esc::String, b) if CANCEL.contains(&b) => (Esc::None, Decoded::DROPPED),
            (Esc::String, b) if b < 0x20 => (Esc::String, Decoded::typed(b)),
            (Esc::String, _) => (Esc::String, Decoded::NOTHING),
            (Esc::StringEnd, b'\\') => (Esc::None, Decoded::DROPPED),
            (Esc::StringEnd, b) => {
                // The string ended without its terminator; this ESC starts a new sequence.
                self.esc = Esc::Start;
                let next = self.byte(b);
                return Decoded {
                    dropped: true,
                    ..next
                };
            }
            // The same rules inside every other sequence.
            (_, 0x1B) => (Esc::Start, Decoded::DROPPED),
            (_, b) if CANCEL.contains(&b) => (Esc::None, Decoded::DROPPED),
            (esc, b) if b < 0x20 => (esc, Decoded::typed(b)),
            (esc, 0x7F) => (esc, Decoded::NOTHING),
            (_, 0x80..) => (
                Esc::None,
                Decoded {
                    dropped: true,
                    key: Some(Key::Typed(b)),
                },
            ),
            (Esc::Start, b'[' | b'O') => (Esc::Csi(Params::default()), Decoded::NOTHING),
            (Esc::Start, b'P' | b'X' | b']' | b'^' | b'_') => (Esc::String, Decoded::NOTHING),
            (Esc::Start | Esc::Intermediate, 0x20..=0x2F) => (Esc::Intermediate, Decoded::NOTHING),
            (Esc::Start | Esc::Intermediate, _) => (Esc::None, Decoded::DROPPED),
            (Esc::Csi(mut params), 0x20..=0x3F) => {
                params.push(b);
                (Esc::Csi(params), Decoded::NOTHING)
            }
            (Esc::Csi(params), _) if params.long => (Esc::None, Decoded::DROPPED),
            (Esc::Csi(params), last) => (
                Esc::None,
                Decoded {
                    dropped: false,
                    key: Some(Key::Csi(Csi { params, last })),
                },
            ),
        };
        self.esc = esc;
        decoded
    }
}

#[cfg(test)]
pub(crate) mod tests;
