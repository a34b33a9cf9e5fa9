//! The telnet layer of the HMI (RFC 854 NVT, RFC 855 option negotiation, RFC 857 ECHO,
//! RFC 858 SUPPRESS-GO-AHEAD): turns the client's raw bytes into [`Input`]s and answers the
//! client's option requests. Runs in the gateway's async tasks, not in the real-time cycle.
//!
//! Choice: the server asks for *character mode with server echo*. On connect it sends
//! `IAC WILL ECHO IAC WILL SUPPRESS-GO-AHEAD` ([`Telnet::greeting`]). A telnet client agrees
//! (`DO ECHO`, `DO SGA`), sends every key as it is pressed and lets the server echo; the
//! [`super::editor`] then gives line editing, history and completion, and the session can
//! redraw the line when a safety error is printed. A client that never answers (e.g. `nc`)
//! keeps editing lines locally in its terminal; the server then echoes nothing
//! ([`Telnet::server_echoes`] stays false), so nothing is shown twice.
//!
//! Every other option the client offers or asks for (terminal type, window size, speed, flow
//! control, LINEMODE, environment, STATUS, ...) is refused once per request; subnegotiations
//! (`IAC SB ... IAC SE`) are skipped without storing them, so memory stays bounded. Line ends
//! CR LF, CR NUL and a bare LF each become one [`Input::Enter`]; `IAC IAC` is the data byte
//! 0xFF. Nothing of the negotiation ever reaches the line.

/// Interpret As Command.
pub const IAC: u8 = 255;
pub const DONT: u8 = 254;
pub const DO: u8 = 253;
pub const WONT: u8 = 252;
pub const WILL: u8 = 251;
/// Subnegotiation begin / end.
pub const SB: u8 = 250;
pub const SE: u8 = 240;
/// Erase line, erase character, are you there, abort output, interrupt process, break.
pub const EL: u8 = 248;
pub const EC: u8 = 247;
pub const AYT: u8 = 246;
pub const AO: u8 = 245;
pub const IP: u8 = 244;
pub const BRK: u8 = 243;
/// End of file (RFC 1184), abort, suspend.
pub const XEOF: u8 = 236;
pub const ABORT: u8 = 238;
pub const SUSP: u8 = 237;
/// Option ECHO (RFC 857).
pub const OPT_ECHO: u8 = 1;
/// Option SUPPRESS-GO-AHEAD (RFC 858).
pub const OPT_SGA: u8 = 3;

/// One unit of client input after the telnet layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// A data byte: a key, or one byte of a UTF-8 character or of an escape sequence.
    Byte(u8),
    /// End of line (CR LF, CR NUL or LF).
    Enter,
    /// `IAC IP`, `IAC BRK`, `IAC ABORT` or `IAC SUSP` (what telnet sends for Ctrl-C in line mode).
    Interrupt,
    /// `IAC EC`.
    EraseChar,
    /// `IAC EL`.
    EraseLine,
    /// `IAC EOF` (Ctrl-D of a client in LINEMODE).
    EndOfFile,
}

/// Our side of one option we support (RFC 1143, without the queue bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Opt {
    No,
    /// We sent WILL and wait for the answer.
    WantYes,
    Yes,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    Data,
    Iac,
    /// After `IAC <verb>`, waiting for the option byte.
    Verb(u8),
    Sub,
    SubIac,
}

/// The telnet state of one connection. Feed it the client's bytes with [`Telnet::feed`].
#[derive(Debug, Clone)]
pub struct Telnet {
    state: State,
    echo: Opt,
    sga: Opt,
    /// The client suppresses go-ahead (it said WILL SGA and we agreed).
    client_sga: bool,
    /// The previous data byte was CR: a following LF or NUL belongs to it.
    after_cr: bool,
}

impl Default for Telnet {
    fn default() -> Self {
        Self::new()
    }
}

impl Telnet {
    /// A new connection; send [`Telnet::greeting`] to the client first.
    pub fn new() -> Self {
        Self {
            state: State::Data,
            echo: Opt::WantYes,
            sga: Opt::WantYes,
            client_sga: false,
            after_cr: false,
        }
    }

    /// The bytes to send on connect: `IAC WILL ECHO IAC WILL SUPPRESS-GO-AHEAD`.
    pub fn greeting() -> [u8; 6] {
        [IAC, WILL, OPT_ECHO, IAC, WILL, OPT_SGA]
    }

    /// True when the client agreed that the server echoes (character mode).
    pub fn server_echoes(&self) -> bool {
        self.echo == Opt::Yes
    }

    /// True inside a telnet command or subnegotiation (a started unit of input).
    pub fn in_sequence(&self) -> bool {
        self.state != State::Data
    }

    /// Decode `bytes`: inputs are appended to `inputs`, negotiation answers to `replies`
    /// (send them to the client).
    pub fn feed(&mut self, bytes: &[u8], inputs: &mut Vec<Input>, replies: &mut Vec<u8>) {
        for &b in bytes {
            self.byte(b, inputs, replies);
        }
    }

    fn byte(&mut self, b: u8, inputs: &mut Vec<Input>, replies: &mut Vec<u8>) {
        match self.state {
            State::Data => {
                if b == IAC {
                    self.state = State::Iac;
                } else {
                    self.data(b, inputs);
                }
            }
            State::Iac => {
                self.state = State::Data;
                match b {
                    IAC => self.data(IAC, inputs),
                    DO | DONT | WILL | WONT => self.state = State::Verb(b),
                    SB => self.state = State::Sub,
                    IP | BRK | ABORT | SUSP => inputs.push(Input::Interrupt),
                    EC => inputs.push(Input::EraseChar),
                    EL => inputs.push(Input::EraseLine),
                    XEOF => inputs.push(Input::EndOfFile),
                    AYT => replies.extend_from_slice(b"\r\n[MCM HMI: yes, here]\r\n"),
                    // Abort output: every line is written at once, nothing waits to be dropped.
                    AO => {}
                    // NOP, DM, GA, SE outside a subnegotiation, EOR: nothing to do.
                    _ => {}
                }
            }
            State::Verb(verb) => {
                self.state = State::Data;
                self.negotiate(verb, b, replies);
            }
            State::Sub => {
                if b == IAC {
                    self.state = State::SubIac;
                }
            }
            State::SubIac => match b {
                SE => self.state = State::Data,
                IAC => self.state = State::Sub,
                // A broken subnegotiation: end it and take the byte as a command.
                other => {
                    self.state = State::Iac;
                    self.byte(other, inputs, replies);
                }
            },
        }
    }

    fn data(&mut self, b: u8, inputs: &mut Vec<Input>) {
        let after_cr = std::mem::replace(&mut self.after_cr, false);
        match b {
            b'\r' => {
                self.after_cr = true;
                inputs.push(Input::Enter);
            }
            b'\n' | 0 if after_cr => {}
            b'\n' => inputs.push(Input::Enter),
            0 => {}
            _ => inputs.push(Input::Byte(b)),
        }
    }

    fn negotiate(&mut self, verb: u8, opt: u8, replies: &mut Vec<u8>) {
        let mut say = |verb: u8| replies.extend_from_slice(&[IAC, verb, opt]);
        match verb {
            DO => match self.ours(opt) {
                Some(state) => {
                    if *state == Opt::No {
                        say(WILL);
                    }
                    *state = Opt::Yes;
                }
                None => say(WONT),
            },
            DONT => {
                if let Some(state) = self.ours(opt) {
                    if *state == Opt::Yes {
                        say(WONT);
                    }
                    *state = Opt::No;
                }
            }
            WILL => {
                if opt == OPT_SGA {
                    if !self.client_sga {
                        self.client_sga = true;
                        say(DO);
                    }
                } else {
                    say(DONT);
                }
            }
            WONT if opt == OPT_SGA && self.client_sga => {
                self.client_sga = false;
                say(DONT);
            }
            _ => {}
        }
    }

    fn ours(&mut self, opt: u8) -> Option<&mut Opt> {
        match opt {
            OPT_ECHO => Some(&mut self.echo),
            OPT_SGA => Some(&mut self.sga),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests;
