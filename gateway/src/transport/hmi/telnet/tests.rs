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
    0xFF, 0xFD, 0x03, 0xFF, 0xFB, 0x18, 0xFF, 0xFB, 0x1F, 0xFF, 0xFB, 0x20, 0xFF, 0xFB, 0x21, 0xFF,
    0xFB, 0x22, 0xFF, 0xFB, 0x27, 0xFF, 0xFD, 0x05,
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
    assert!(t.server_echoes());
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
