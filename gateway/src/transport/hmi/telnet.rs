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
    /// The client sent at least one IAC sequence (it speaks telnet).
    seen_iac: bool,
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
            seen_iac: false,
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

    /// True once the client sent any telnet command.
    #[cfg(test)]
    pub fn speaks_telnet(&self) -> bool {
        self.seen_iac
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
                    self.seen_iac = true;
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
mod tests {
    use super::super::editor::{Action, Editor};
    use super::*;

    fn feed(t: &mut Telnet, bytes: &[u8]) -> (Vec<Input>, Vec<u8>) {
        let (mut i, mut r) = (Vec::new(), Vec::new());
        t.feed(bytes, &mut i, &mut r);
        (i, r)
    }

    /// What Linux (netkit) telnet sends on connect to a telnet port: DO SGA, WILL TTYPE,
    /// WILL NAWS, WILL TSPEED, WILL LFLOW, WILL LINEMODE, WILL NEW-ENVIRON, DO STATUS.
    const LINUX_TELNET_HELLO: &[u8] = &[
        0xFF, 0xFD, 0x03, 0xFF, 0xFB, 0x18, 0xFF, 0xFB, 0x1F, 0xFF, 0xFB, 0x20, 0xFF, 0xFB, 0x21,
        0xFF, 0xFB, 0x22, 0xFF, 0xFB, 0x27, 0xFF, 0xFD, 0x05,
    ];

    /// Linux telnet answers the greeting, then types "hi" and Enter (CR NUL).
    #[test]
    fn the_greeting_agreed_then_a_typed_line() {
        let mut t = Telnet::new();
        let (inputs, replies) = feed(&mut t, &[255, 253, 1, 255, 253, 3, b'h', b'i', b'\r', 0]);
        assert_eq!(inputs, [Input::Byte(b'h'), Input::Byte(b'i'), Input::Enter]);
        assert!(t.server_echoes());
        assert!(
            replies.is_empty(),
            "the DOs acknowledged our WILLs: nothing to answer"
        );
    }

    #[test]
    fn linux_telnet_hello_is_answered_and_yields_no_input() {
        let mut t = Telnet::new();
        let (inputs, replies) = feed(&mut t, LINUX_TELNET_HELLO);
        assert!(inputs.is_empty(), "{inputs:?}");
        // DO SGA acknowledges our WILL SGA; every WILL is refused with DONT; DO STATUS gets WONT.
        let expected: Vec<u8> = [
            [IAC, DONT, 0x18],
            [IAC, DONT, 0x1F],
            [IAC, DONT, 0x20],
            [IAC, DONT, 0x21],
            [IAC, DONT, 0x22],
            [IAC, DONT, 0x27],
            [IAC, WONT, 0x05],
        ]
        .concat();
        assert_eq!(replies, expected);
        assert!(!t.server_echoes(), "ECHO not agreed yet");
        let (inputs, replies) = feed(&mut t, &[IAC, DO, OPT_ECHO]);
        assert!(inputs.is_empty() && replies.is_empty());
        assert!(t.server_echoes() && t.speaks_telnet());
    }

    #[test]
    fn negotiation_does_not_loop() {
        let mut t = Telnet::new();
        // Repeated acknowledgements are not answered again.
        let (_, r) = feed(&mut t, &[IAC, DO, OPT_ECHO, IAC, DO, OPT_ECHO]);
        assert!(r.is_empty());
        // The client turns echo off (telnet `mode line`): we confirm once.
        let (_, r) = feed(&mut t, &[IAC, DONT, OPT_ECHO, IAC, DONT, OPT_ECHO]);
        assert_eq!(r, [IAC, WONT, OPT_ECHO]);
        assert!(!t.server_echoes());
        // ... and back on: we agree once.
        let (_, r) = feed(&mut t, &[IAC, DO, OPT_ECHO]);
        assert_eq!(r, [IAC, WILL, OPT_ECHO]);
        // Client offers SGA: accepted once; withdrawn: confirmed once.
        let (_, r) = feed(&mut t, &[IAC, WILL, OPT_SGA, IAC, WILL, OPT_SGA]);
        assert_eq!(r, [IAC, DO, OPT_SGA]);
        let (_, r) = feed(&mut t, &[IAC, WONT, OPT_SGA, IAC, WONT, OPT_SGA]);
        assert_eq!(r, [IAC, DONT, OPT_SGA]);
        // A refusal of our offer is not answered.
        let mut t = Telnet::new();
        let (_, r) = feed(&mut t, &[IAC, DONT, OPT_ECHO, IAC, WONT, 0x18]);
        assert!(r.is_empty() && !t.server_echoes());
    }

    #[test]
    fn subnegotiation_is_skipped_even_split_across_reads() {
        let mut t = Telnet::new();
        // NAWS 80x24 containing an escaped 255, then "ok".
        let sb = [
            IAC, SB, 0x1F, 0, 80, IAC, IAC, 24, IAC, SE, b'o', b'k', b'\n',
        ];
        for split in 0..sb.len() {
            let mut t2 = t.clone();
            let (mut a, _) = feed(&mut t2, &sb[..split]);
            let (b, _) = feed(&mut t2, &sb[split..]);
            a.extend(b);
            assert_eq!(
                a,
                [Input::Byte(b'o'), Input::Byte(b'k'), Input::Enter],
                "split {split}"
            );
        }
        // Terminal type reply: IAC SB TTYPE IS "XTERM" IAC SE.
        let (i, r) = feed(&mut t, b"\xFF\xFA\x18\x00XTERM\xFF\xF0");
        assert!(i.is_empty() && r.is_empty());
    }

    #[test]
    fn escaped_iac_is_a_data_byte_and_commands_are_inputs() {
        let mut t = Telnet::new();
        let (i, _) = feed(
            &mut t,
            &[IAC, IAC, IAC, IP, IAC, EC, IAC, EL, IAC, XEOF, IAC, 241],
        );
        assert_eq!(
            i,
            [
                Input::Byte(0xFF),
                Input::Interrupt,
                Input::EraseChar,
                Input::EraseLine,
                Input::EndOfFile
            ]
        );
        let (_, r) = feed(&mut t, &[IAC, AYT]);
        assert!(String::from_utf8_lossy(&r).contains("yes"));
    }

    #[test]
    fn line_ends_cr_lf_cr_nul_and_lf() {
        let mut t = Telnet::new();
        let (i, _) = feed(&mut t, b"a\r\nb\r\0c\nd\r");
        let (j, _) = feed(&mut t, b"\0e\r\r\n");
        let enters = |v: &[Input]| v.iter().filter(|x| **x == Input::Enter).count();
        assert_eq!(enters(&i), 4);
        assert_eq!(
            j,
            [Input::Byte(b'e'), Input::Enter, Input::Enter],
            "CR NUL split across reads, then an empty line"
        );
    }

    fn lines(bytes: &[u8]) -> Vec<String> {
        let mut t = Telnet::new();
        let mut e = Editor::new(1024, Vec::new());
        let (inputs, _) = feed(&mut t, bytes);
        let mut out = Vec::new();
        inputs
            .into_iter()
            .filter_map(|i| match e.feed(i, t.server_echoes(), &mut out) {
                Some(Action::Line(l)) => Some(l),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn backspace_through_the_telnet_layer() {
        // 0x7F (Linux telnet in character mode) and 0x08 (Ctrl-H), with and without echo.
        assert_eq!(lines(b"statux\x7Fs\r\0"), ["status"]);
        assert_eq!(lines(b"\xFF\xFD\x01holf\x08d\r\n"), ["hold"]);
        assert_eq!(lines(b"ab\xFF\xF7c\n"), ["ac"]);
        assert_eq!(lines(&[LINUX_TELNET_HELLO, b"info\r\0"].concat()), ["info"]);
    }
}
