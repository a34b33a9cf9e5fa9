//! End to end: the text HMI (telnet, port 18011) against the running robot. The tests speak to
//! the HMI as the Linux `telnet` program does (its option negotiation, character mode with
//! server echo, CR NUL line ends, DEL for backspace) and as `nc` does (no negotiation at all).
//! Every wait is bounded: read until the expected text appears or [`WAIT`] passes.

use crate::common;

use common::{Mcm, WAIT};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::Instant;

const IAC: u8 = 255;
const DONT: u8 = 254;
const DO: u8 = 253;
const WONT: u8 = 252;
const WILL: u8 = 251;
const SB: u8 = 250;
const SE: u8 = 240;
const ECHO: u8 = 1;
const SGA: u8 = 3;
const STATUS: u8 = 5;
/// Terminal type, window size, terminal speed, flow control, LINEMODE, NEW-ENVIRON.
const OFFERED: [u8; 6] = [0x18, 0x1F, 0x20, 0x21, 0x22, 0x27];

/// What Linux (netkit) `telnet` sends first: DO SGA, WILL TTYPE, WILL NAWS, WILL TSPEED,
/// WILL LFLOW, WILL LINEMODE, WILL NEW-ENVIRON, DO STATUS.
const LINUX_TELNET_HELLO: [u8; 24] = [
    0xFF, 0xFD, 0x03, 0xFF, 0xFB, 0x18, 0xFF, 0xFB, 0x1F, 0xFF, 0xFB, 0x20, 0xFF, 0xFB, 0x21, 0xFF,
    0xFB, 0x22, 0xFF, 0xFB, 0x27, 0xFF, 0xFD, 0x05,
];

/// The commands of the manual; `help` must list each of them.
const MANUAL_COMMANDS: [&str; 13] = [
    "status",
    "info",
    "hold",
    "sleep",
    "sim",
    "calibrate",
    "release",
    "pvt",
    "torque_control",
    "move_axis",
    "move_all",
    "pvt_points",
    "set_torques",
];

/// The P-Rob2's axis names, in order.
const AXIS_NAMES: [&str; 6] = ["base", "shoulder", "elbow", "forearm", "wrist", "flange"];

/// Remove ANSI CSI sequences (`ESC [ params final`), as a terminal would not show them.
fn strip_ansi(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '\x1b' {
            out.push(c);
            continue;
        }
        if chars.next_if_eq(&'[').is_some() {
            for c in chars.by_ref() {
                if ('\x40'..='\x7e').contains(&c) {
                    break;
                }
            }
        }
    }
    out
}

/// Assert that `data` (the server's output without telnet commands) is text a terminal shows
/// cleanly: UTF-8 (so no stray 0xFF), and no control bytes other than CR, LF, backspace and
/// complete ANSI sequences.
fn assert_clean(data: &[u8]) {
    let text = std::str::from_utf8(data).unwrap_or_else(|e| {
        panic!(
            "output is not UTF-8 ({e}): {:?}",
            String::from_utf8_lossy(data)
        )
    });
    let plain = strip_ansi(text);
    for (i, c) in plain.char_indices() {
        assert!(
            !c.is_control() || matches!(c, '\r' | '\n' | '\x08'),
            "control character {c:?} in the output at {i}: {:?}",
            &plain[i.saturating_sub(80)..(i + 40).min(plain.len())]
        );
    }
}

/// Something the reader thread saw.
enum Event {
    /// Data bytes (telnet commands removed).
    Data(Vec<u8>),
    /// `IAC <verb> <option>` from the server.
    Command(u8, u8),
    /// The server closed the connection.
    Closed,
}

/// The client's side of the options, as Linux telnet keeps it (RFC 1143 without queues).
#[derive(Default)]
struct Options {
    /// Options we offered with WILL or agreed to; `true` once the server said DO.
    ours: Vec<(u8, bool)>,
    /// Options we asked the server for with DO or agreed to; `true` once it said WILL.
    theirs: Vec<(u8, bool)>,
}

impl Options {
    fn linux_telnet() -> Self {
        Options {
            ours: OFFERED.iter().map(|&o| (o, false)).collect(),
            theirs: vec![(SGA, false), (STATUS, false)],
        }
    }

    /// The answer to `IAC verb opt`, if any; the client accepts the server's ECHO and SGA.
    fn answer(&mut self, verb: u8, opt: u8) -> Option<[u8; 3]> {
        let find = |list: &mut Vec<(u8, bool)>| list.iter().position(|(o, _)| *o == opt);
        match verb {
            WILL => match find(&mut self.theirs) {
                Some(i) => {
                    // An answer to our DO (no reply), or a repeat (no reply).
                    self.theirs[i].1 = true;
                    None
                }
                None if opt == ECHO || opt == SGA => {
                    self.theirs.push((opt, true));
                    Some([IAC, DO, opt])
                }
                None => Some([IAC, DONT, opt]),
            },
            WONT => {
                let i = find(&mut self.theirs)?;
                let (_, was_on) = self.theirs.remove(i);
                was_on.then_some([IAC, DONT, opt])
            }
            DO => match find(&mut self.ours) {
                Some(i) => {
                    self.ours[i].1 = true;
                    None
                }
                None => Some([IAC, WONT, opt]),
            },
            DONT => {
                let i = find(&mut self.ours)?;
                let (_, was_on) = self.ours.remove(i);
                was_on.then_some([IAC, WONT, opt])
            }
            _ => None,
        }
    }
}

/// Decode the server's bytes (RFC 854): data, `IAC <verb> <opt>`, skipped subnegotiations.
fn reader(mut stream: TcpStream, writer: Arc<Mutex<TcpStream>>, tx: mpsc::Sender<Event>) {
    #[derive(Clone, Copy)]
    enum St {
        Data,
        Iac,
        Verb(u8),
        Sub,
        SubIac,
    }
    let mut options = Options::linux_telnet();
    let mut st = St::Data;
    let mut buf = [0u8; 4096];
    loop {
        let n = match stream.read(&mut buf) {
            Ok(0) | Err(_) => {
                let _ = tx.send(Event::Closed);
                return;
            }
            Ok(n) => n,
        };
        let mut data = Vec::new();
        let mut events = Vec::new();
        for &b in &buf[..n] {
            st = match (st, b) {
                (St::Data, IAC) => St::Iac,
                (St::Data, _) => {
                    data.push(b);
                    St::Data
                }
                (St::Iac, IAC) => {
                    data.push(IAC);
                    St::Data
                }
                (St::Iac, WILL | WONT | DO | DONT) => St::Verb(b),
                (St::Iac, SB) => St::Sub,
                (St::Iac, _) => St::Data,
                (St::Verb(verb), opt) => {
                    if let Some(reply) = options.answer(verb, opt) {
                        // Answer at once, before the data that follows is looked at: the
                        // server sees our DO ECHO before anything we type.
                        writer.lock().unwrap().write_all(&reply).unwrap();
                    }
                    if !data.is_empty() {
                        events.push(Event::Data(std::mem::take(&mut data)));
                    }
                    events.push(Event::Command(verb, opt));
                    St::Data
                }
                (St::Sub, IAC) => St::SubIac,
                (St::Sub, _) => St::Sub,
                (St::SubIac, SE) => St::Data,
                (St::SubIac, _) => St::Sub,
            };
        }
        if !data.is_empty() {
            events.push(Event::Data(data));
        }
        for e in events {
            if tx.send(e).is_err() {
                return;
            }
        }
    }
}

/// A telnet client with an expect-style reader.
pub(crate) struct Telnet {
    writer: Arc<Mutex<TcpStream>>,
    rx: mpsc::Receiver<Event>,
    /// Every data byte received (telnet commands removed).
    data: Vec<u8>,
    /// Every telnet command received.
    commands: Vec<(u8, u8)>,
    /// How much of [`Telnet::text`] the test has consumed.
    seen: usize,
    closed: bool,
}

impl Telnet {
    /// Connect and send what Linux telnet sends first.
    pub(crate) fn connect(addr: SocketAddr) -> Telnet {
        let stream = TcpStream::connect(addr).expect("connect to the HMI");
        stream.set_nodelay(true).unwrap();
        let writer = Arc::new(Mutex::new(stream.try_clone().unwrap()));
        let (tx, rx) = mpsc::channel();
        let w = writer.clone();
        std::thread::spawn(move || reader(stream, w, tx));
        let mut t = Telnet {
            writer,
            rx,
            data: Vec::new(),
            commands: Vec::new(),
            seen: 0,
            closed: false,
        };
        t.send(&LINUX_TELNET_HELLO);
        t
    }

    pub(crate) fn send(&mut self, bytes: &[u8]) {
        self.writer.lock().unwrap().write_all(bytes).unwrap();
    }

    /// The output as a terminal shows it: UTF-8, ANSI sequences removed.
    fn text(&self) -> String {
        strip_ansi(&String::from_utf8_lossy(&self.data))
    }

    /// Wait for one event; false when the deadline passed.
    fn pump(&mut self, deadline: Instant) -> bool {
        let left = deadline.saturating_duration_since(Instant::now());
        match self.rx.recv_timeout(left) {
            Ok(Event::Data(d)) => self.data.extend_from_slice(&d),
            Ok(Event::Command(v, o)) => self.commands.push((v, o)),
            Ok(Event::Closed) => self.closed = true,
            Err(RecvTimeoutError::Timeout) => return false,
            Err(RecvTimeoutError::Disconnected) => self.closed = true,
        }
        true
    }

    /// Read until `done` holds for the unconsumed text; panic after [`WAIT`].
    fn wait_for(&mut self, what: &str, done: impl Fn(&str) -> bool) {
        let deadline = Instant::now() + WAIT;
        loop {
            if done(&self.text()[self.seen..]) {
                return;
            }
            if self.closed || !self.pump(deadline) {
                panic!(
                    "{what}: not seen within {WAIT:?} (closed: {}); unconsumed output:\n{}",
                    self.closed,
                    &self.text()[self.seen..]
                );
            }
        }
    }

    /// Read until `needle` appears; return the text up to and including it, and consume it.
    pub(crate) fn expect(&mut self, needle: &str) -> String {
        self.wait_for(&format!("{needle:?}"), |t| t.contains(needle));
        let text = self.text();
        let end = self.seen + text[self.seen..].find(needle).unwrap() + needle.len();
        let got = text[self.seen..end].to_string();
        self.seen = end;
        got
    }

    /// Type `line` with the line end `eol`, check the server echoes exactly the line and a new
    /// row (nothing else before it: no stray prompt, no echoed negotiation), then return the
    /// output up to the next prompt `mcm <mode>> `.
    pub(crate) fn run(&mut self, line: &str, eol: &[u8], mode: &str) -> String {
        let mut bytes = line.as_bytes().to_vec();
        bytes.extend_from_slice(eol);
        self.send(&bytes);
        let echo = format!("{line}\r\n");
        self.wait_for("the echo", |t| t.len() >= echo.len());
        let text = self.text();
        assert!(
            text[self.seen..].starts_with(&echo),
            "expected the echo {echo:?}, got {:?}",
            &text[self.seen..]
        );
        self.seen += echo.len();
        let out = self.expect(&format!("mcm {mode}> "));
        out.strip_suffix(&format!("mcm {mode}> "))
            .unwrap()
            .to_string()
    }

    /// Wait until the server closed the connection.
    fn expect_closed(&mut self) {
        let deadline = Instant::now() + WAIT;
        while !self.closed {
            assert!(
                self.pump(deadline),
                "the connection is still open {WAIT:?} later"
            );
        }
    }
}

/// Check a status table: header, unit row and six axis rows, every value right-aligned under
/// its column title. Returns the axis rows.
fn assert_status_table(out: &str, mode: &str) -> Vec<String> {
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[0].starts_with(&format!("mode {mode} - ")),
        "first line names the mode {mode}: {out}"
    );
    let h = lines
        .iter()
        .position(|l| l.starts_with("axis  name"))
        .unwrap_or_else(|| panic!("no table header in:\n{out}"));
    let header = lines[h];
    let columns = ["position", "velocity", "current"];
    let ends: Vec<usize> = columns
        .iter()
        .map(|c| {
            header
                .find(c)
                .unwrap_or_else(|| panic!("{c} in {header:?}"))
                + c.len()
        })
        .collect();
    // The unit row: each unit ends where its column title ends.
    let units = lines[h + 1];
    for (unit, end) in ["deg", "deg/s", "A"].iter().zip(&ends) {
        assert_eq!(
            units.get(end - unit.len()..*end),
            Some(*unit),
            "unit {unit} under its column:\n{header}\n{units}"
        );
    }
    let rows: Vec<String> = lines[h + 2..h + 8].iter().map(|l| l.to_string()).collect();
    for (i, row) in rows.iter().enumerate() {
        let words: Vec<&str> = row.split_whitespace().collect();
        assert_eq!(words[0], (i + 1).to_string(), "axis number: {row:?}");
        assert_eq!(words[1], AXIS_NAMES[i], "axis name: {row:?}");
        for (c, end) in columns.iter().zip(&ends) {
            // The value ending at the column's right edge is a number (or "-").
            let cell = row
                .get(..*end)
                .and_then(|s| s.rsplit(' ').next())
                .unwrap_or_default();
            assert!(
                cell == "-" || cell.parse::<f64>().is_ok(),
                "{c} of axis {} is not aligned under its title:\n{header}\n{row}",
                i + 1
            );
            assert!(
                row.len() == *end || row.as_bytes().get(*end) == Some(&b' '),
                "{c} of axis {} runs past its column:\n{header}\n{row}",
                i + 1
            );
        }
    }
    let after = lines.get(h + 8).copied().unwrap_or_default();
    assert!(
        !after.trim_start().starts_with('7'),
        "exactly six axis rows: {out}"
    );
    rows
}

#[test]
fn a_telnet_session_negotiates_helps_shows_tables_and_refuses_helpfully() {
    let mcm = Mcm::start("hmi-telnet");
    let mut t = Telnet::connect(mcm.hmi);

    // The banner: version, robot, mode, how to start; then the prompt.
    let banner = t.expect("mcm OFF> ");
    for w in [
        &format!(
            "MCM {} - Motion Control Module, text HMI\r\n",
            mcm_shared::VERSION
        ),
        "robot: P-Rob2\r\n",
        "mode:  OFF - drives powered off",
        "Type `help` for the commands",
    ] {
        assert!(banner.contains(w), "banner lacks {w:?}:\n{banner}");
    }
    assert_eq!(
        &t.data[..9],
        b"\r\x1b[K\x1b[1mM",
        "the banner starts on a cleared row"
    );

    // The negotiation: the server offers ECHO and SGA, refuses each option telnet offered
    // (DONT) and STATUS (WONT), and then says nothing more (no negotiation loop).
    let mut expected: Vec<(u8, u8)> = vec![(WILL, ECHO), (WILL, SGA)];
    expected.extend(OFFERED.iter().map(|&o| (DONT, o)));
    expected.push((WONT, STATUS));
    let deadline = Instant::now() + WAIT;
    while t.commands.len() < expected.len() {
        assert!(t.pump(deadline), "negotiation so far: {:?}", t.commands);
    }
    assert_eq!(t.commands, expected);

    // `help` (CR LF): every command, one line each; the echo right after the prompt shows that
    // none of the negotiation bytes (0x18, ' ', '!', '"', '\'' ...) was taken as typed text.
    let help = t.run("help", b"\r\n", "OFF");
    let listed = |name: &str| {
        help.lines()
            .any(|l| l.starts_with("  ") && l.split_whitespace().next() == Some(name))
    };
    for name in MANUAL_COMMANDS
        .iter()
        .copied()
        .chain(mcm_shared::protocol::command_names())
        .chain(["help", "watch", "clear", "quit,"])
    {
        assert!(listed(name), "`help` does not list {name}:\n{help}");
    }
    assert!(help.contains("`help CMD` explains one"), "{help}");
    assert!(
        help.contains("A line starting with { is a JSON command"),
        "{help}"
    );

    // `help move_axis` (LF): arguments with units, defaults, modes, examples, limits.
    let h = t.run("help move_axis", b"\n", "OFF");
    for w in [
        "move_axis - move one axis to a target position",
        "usage:       move_axis <axis_index> <target_position> [velocity_factor]",
        "axis_index (axis)",
        "the axis, 1..6",
        "target angle [deg]",
        "velocity_factor (vf)",
        "default 0.33333",
        "accepted in: PVT",
        "examples:",
        // The reachable range (the table of ranges), not the joint limits -170..170.
        "reachable positions [deg] (the axis limits less the 1 deg safety margin): \
         1 base -169..169",
        "max velocity [deg/s]",
    ] {
        assert!(h.contains(w), "`help move_axis` lacks {w:?}:\n{h}");
    }

    // `status` (CR NUL, what telnet sends for Enter): an aligned table with six axis rows.
    let s = t.run("status", b"\r\0", "OFF");
    assert_status_table(&s, "OFF");

    // A wrong argument: what is wrong, what is allowed, the usage and where to read more.
    let e = t.run("move_axis 9 0", b"\r\0", "OFF");
    for w in [
        "error [out_of_range]: move_axis: argument \"axis_index\" = 9 is not allowed",
        "1 to 6",
        "usage: move_axis <axis_index> <target_position> [velocity_factor]",
        "`help move_axis`",
    ] {
        assert!(e.contains(w), "{w:?} in:\n{e}");
    }

    // A typo gets a suggestion.
    let e = t.run("stauts", b"\r\0", "OFF");
    assert!(
        e.contains(
            "error [unknown_command]: unknown command \"stauts\" (did you mean \"status\"?)"
        ),
        "{e}"
    );

    // A command the robot refuses in this mode says why and how to get there.
    let e = t.run("release", b"\r\0", "OFF");
    assert!(
        e.contains("error [wrong_mode]: ") && e.contains("OFF") && e.contains("hint: "),
        "{e}"
    );

    // A line starting with `{` is a JSON command; the reply is (pretty) JSON.
    let j = t.run(r#"{"command":"info"}"#, b"\r\0", "OFF");
    let v: serde_json::Value =
        serde_json::from_str(&j.replace("\r\n", "\n")).unwrap_or_else(|e| panic!("{e}: {j}"));
    assert_eq!(v["result_type"], "initialization", "{v}");
    assert_eq!(v["robot"], "P-Rob2", "{v}");
    assert_eq!(v["num_axes"], 6, "{v}");
    let j = t.run(r#"{"command":"stauts"}"#, b"\n", "OFF");
    assert!(
        j.contains("\"error_status\": \"ERROR\"") && j.contains("did you mean"),
        "{j}"
    );

    // Backspace (telnet sends DEL): `statux`, backspace, `s` is `status`; the server erases
    // the character on the screen.
    t.send(b"statux\x7fs\r\0");
    let echo = t.expect("\r\n");
    assert_eq!(echo, "statux\x08 \x08s\r\n");
    let s = t.expect("mcm OFF> ");
    assert_status_table(&s, "OFF");

    // An empty line gives a fresh prompt; a bare CR ends a line too.
    let e = t.run("", b"\r\n", "OFF");
    assert_eq!(e, "");
    let e = t.run("sleep 0.01", b"\r", "OFF");
    assert!(e.contains("OK"), "{e}");

    // `quit` says goodbye and closes the connection.
    t.send(b"quit\r\0");
    assert_eq!(t.expect("bye\r\n"), "quit\r\nbye\r\n");
    t.expect_closed();

    // Everything the server sent was clean text; the negotiation never changed after start.
    assert_clean(&t.data);
    assert_eq!(t.commands, expected);
    assert_eq!(
        t.text()[t.seen..].to_string(),
        "",
        "nothing after the goodbye"
    );
}

#[test]
fn hold_changes_the_prompt_and_a_safety_error_from_elsewhere_is_shown() {
    let mcm = Mcm::start("hmi-hold");
    let mut json = mcm.client();
    json.wait_drives_online();
    let mut t = Telnet::connect(mcm.hmi);
    t.expect("mcm OFF> ");

    let s = t.run("hold", b"\r\0", "HOLD");
    assert_status_table(&s, "HOLD");
    let s = t.run("status detail", b"\r\0", "HOLD");
    let rows = assert_status_table(&s, "HOLD");
    assert!(
        rows.iter()
            .all(|r| r.ends_with(" NO") || r.ends_with(" yes")),
        "the detail columns end with `calibrated`: {rows:?}"
    );
    for w in [
        "hardware:  drives online 6/6, enabled 6/6",
        "cycle:",
        "PVT queue:",
    ] {
        assert!(s.contains(w), "{w:?} in:\n{s}");
    }

    // Half a command typed, then another client disconnects axis 2: the error is printed
    // above the line, and the line is redrawn with the new mode.
    t.send(b"stat");
    t.expect("stat");
    let r = json.request(r#"{"command":"sim","arguments":{"disconnect_axis":2}}"#);
    assert_eq!(r["result_type"], "sim", "{r}");
    let e = t.expect("`hold` clears the error");
    for w in [
        "*** safety check tripped",
        "the drive of axis 2 does not answer on the bus",
        "mode is now ERROR",
        "hint: once the cause is gone, `hold` clears the error",
    ] {
        assert!(e.contains(w), "{w:?} in:\n{e}");
    }
    t.expect("mcm ERROR> stat");
    let s = t.run("us", b"\r\0", "ERROR");
    assert_status_table(&s, "ERROR");
    assert!(
        s.contains("last error: safety check tripped: the drive of axis 2"),
        "{s}"
    );

    t.send(b"exit\r\n");
    t.expect("bye\r\n");
    t.expect_closed();
    assert_clean(&t.data);
}

/// Type `typed` at the HMI as `nc` does (no negotiation), at once; everything the HMI sends
/// until it closes the connection.
fn nc_session(hmi: SocketAddr, typed: &[u8]) -> Vec<u8> {
    let mut s = TcpStream::connect(hmi).expect("connect to the HMI");
    s.set_read_timeout(Some(WAIT)).unwrap();
    s.write_all(typed).unwrap();
    let deadline = Instant::now() + WAIT;
    let mut out = Vec::new();
    let mut buf = [0u8; 4096];
    loop {
        assert!(
            Instant::now() < deadline,
            "not closed within {WAIT:?}; got {:?}",
            String::from_utf8_lossy(&out)
        );
        match s.read(&mut buf) {
            Ok(0) => return out,
            Ok(n) => out.extend_from_slice(&buf[..n]),
            Err(e) => panic!(
                "no close within {WAIT:?} ({e}); got {:?}",
                String::from_utf8_lossy(&out)
            ),
        }
    }
}

#[test]
fn nc_style_use_without_negotiation_gets_readable_output_and_a_close() {
    let mcm = Mcm::start("hmi-nc");
    // Typed ahead, before the banner arrived, with plain LF line ends.
    let out = nc_session(mcm.hmi, b"status\nquit\n");
    // The offer of ECHO and SGA comes first; right after it the row is cleared, so a terminal
    // shows nothing of it. Everything after it is clean text.
    let greeting = [IAC, WILL, ECHO, IAC, WILL, SGA];
    assert_eq!(&out[..6], greeting, "{out:?}");
    assert_eq!(&out[6..10], b"\r\x1b[K", "{out:?}");
    let rest = &out[6..];
    assert!(
        !rest.contains(&IAC),
        "no telnet commands after the greeting"
    );
    assert_clean(rest);
    let text = strip_ansi(std::str::from_utf8(rest).unwrap());
    assert!(text.contains("robot: P-Rob2\r\n"), "{text}");
    // No echo without negotiation (the terminal shows what was typed): the table follows the
    // prompt directly.
    let (_, after) = text
        .split_once("mcm OFF> ")
        .unwrap_or_else(|| panic!("no prompt: {text}"));
    assert!(after.starts_with("mode OFF - "), "{after}");
    let (table, tail) = after
        .split_once("mcm OFF> ")
        .unwrap_or_else(|| panic!("no second prompt: {after}"));
    assert_status_table(&table.replace("\r\n", "\n"), "OFF");
    assert_eq!(tail, "bye\r\n");
}

/// Every escape sequence in `out` is one the HMI itself writes (its colours, cursor and line
/// control); an ESC from elsewhere (configuration text) fails, naming where.
fn assert_only_own_escapes(out: &str) {
    let own = [
        "\x1b[1;31m",
        "\x1b[32m",
        "\x1b[33m",
        "\x1b[1m",
        "\x1b[0m",
        "\x1b[K",
        "\x1b[J",
        "\x1b[?25h",
        "\x1b[?25l",
    ];
    for (i, _) in out.match_indices('\x1b') {
        let rest = &out[i..];
        assert!(
            own.iter().any(|e| rest.starts_with(e)),
            "an escape sequence the HMI does not write at {i}: {:?}",
            &rest[..rest.len().min(40)]
        );
    }
}

/// A robot and an axis name holding escape sequences (a hostile or careless configuration)
/// reach the banner, `info` and `status` shown visibly, never as control codes: the screen is
/// not cleared, the title not set, the line not overwritten.
#[test]
fn configuration_text_with_escape_sequences_is_shown_visibly() {
    let config = common::config_file("hmi-esc", |base| {
        let text = base
            .replace("name = \"P-Rob2\"", "name = \"P-Rob2\\u001b[2J\"")
            .replace("name = \"base\"", "name = \"b\\u001b]0;x\\u0007\\r\"");
        assert!(text.contains("\\u001b[2J") && text.contains("\\u001b]0;x"));
        text
    });
    let mcm = Mcm::start_with("hmi-esc", &["--config", config.path()]);
    let out = nc_session(mcm.hmi, b"info\nstatus\nquit\n");
    // After the telnet greeting (IAC WILL ECHO, IAC WILL SGA).
    let text = std::str::from_utf8(&out[6..]).expect("ASCII output");
    assert_only_own_escapes(text);
    assert!(
        !text.contains('\x07'),
        "no BEL (it ends a title sequence): {text:?}"
    );
    let plain = strip_ansi(text);
    assert!(plain.contains("robot: P-Rob2^[[2J\r\n"), "banner: {plain}");
    assert!(plain.contains("P-Rob2^[[2J, MCM "), "info: {plain}");
    assert!(plain.contains("b^[]0;x^G^M"), "axis name in info: {plain}");
    assert!(plain.contains("bye\r\n"), "{plain}");
}

/// What the issue asks of the HMI: a person calibrates the arm, moves it and reads its state with
/// words only, and the simulation's truth agrees.
#[test]
fn a_person_calibrates_moves_and_reads_the_state_with_words() {
    let mcm = Mcm::start("hmi-motion");
    let mut json = mcm.client();
    json.wait_drives_online();
    let mut t = Telnet::connect(mcm.hmi);
    t.expect("mcm OFF> ");

    // Calibration runs about 12 s; the prompt comes back when it is done.
    let out = t.run("calibrate", b"\r\n", "HOLD");
    assert!(!out.contains("ERROR"), "calibrate failed:\n{out}");
    let s = t.run("status detail", b"\r\n", "HOLD");
    let rows = assert_status_table(&s, "HOLD");
    assert!(
        rows.iter().all(|r| r.ends_with(" yes")),
        "all calibrated: {rows:?}"
    );

    t.run("pvt", b"\r\n", "PVT");
    let out = t.run("move_axis 1 20 1.0", b"\r\n", "PVT");
    assert!(
        !out.contains("ERROR") && !out.contains("refused"),
        "move_axis:\n{out}"
    );
    // At the end of the move (the HMI shows three decimals).
    json.wait_status("axis 1 at 20 deg", |s| {
        (s["axis_states"]["position"][0].as_f64().unwrap_or(0.0) - 20.0).abs() < 0.0005
    });
    let truth = json.request(r#"{"command":"sim"}"#);
    let true_deg = truth["true_position"][0].as_f64().unwrap();
    assert!(
        (true_deg - 20.0).abs() < 0.05,
        "the simulated arm is at 20 deg: {truth}"
    );
    let s = t.run("status", b"\r\n", "PVT");
    let rows = assert_status_table(&s, "PVT");
    assert!(
        rows[0].contains("20.000"),
        "axis 1 row shows 20 deg: {}",
        rows[0]
    );

    // A motion command in the wrong mode explains how to get there.
    t.run("hold", b"\r\n", "HOLD");
    let out = t.run("move_axis 1 0", b"\r\n", "HOLD");
    assert!(out.contains("HOLD"), "names the mode:\n{out}");
    t.send(b"quit\r\n");
    t.expect("bye\r\n");
    t.expect_closed();
}
