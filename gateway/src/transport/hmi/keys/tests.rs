//! The key decoder byte by byte, and property tests over escape sequences of every kind; the
//! sequence generator is shared with the tests of the editor and the jog screen.

use super::*;
use proptest::prelude::*;

/// What `bytes` give, one entry per byte that completed something: `Typed` bytes, keys as
/// `(params, last)`, and `Dropped` for each sequence dropped.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Out {
    Typed(u8),
    Key(String, u8),
    Dropped,
}

fn decode(bytes: &[u8]) -> Vec<Out> {
    let mut d = KeyDecoder::default();
    let mut out = Vec::new();
    for &b in bytes {
        let Decoded { dropped, key } = d.byte(b);
        if dropped {
            out.push(Out::Dropped);
        }
        match key {
            Some(Key::Typed(b)) => out.push(Out::Typed(b)),
            Some(Key::Csi(k)) => out.push(Out::Key(k.params().to_string(), k.last)),
            None => {}
        }
    }
    out
}

fn key(params: &str, last: u8) -> Out {
    Out::Key(params.to_string(), last)
}

#[test]
fn keys_typed_bytes_and_dropped_sequences() {
    use Out::*;
    assert_eq!(
        decode(b"a\x1b[Ab"),
        [Typed(b'a'), key("", b'A'), Typed(b'b')]
    );
    assert_eq!(
        decode(b"\x1bOA\x1b[1;5C\x1b[3~"),
        [key("", b'A'), key("1;5", b'C'), key("3", b'~')]
    );
    // A title string (OSC), ended by BEL or by ST, and a charset designation: no keys.
    assert_eq!(decode(b"\x1b]0;+x\x07+"), [Dropped, Typed(b'+')]);
    assert_eq!(decode(b"\x1b]2;-\x1b\\\x1b(B"), [Dropped, Dropped]);
    // Alt-x is dropped whole.
    assert_eq!(decode(b"\x1bx"), [Dropped]);
    // Parameters longer than a key's: dropped whole.
    let long = format!("\x1b[{}A", "1;".repeat(40));
    assert_eq!(decode(long.as_bytes()), [Dropped]);
}

#[test]
fn controls_act_inside_a_sequence_and_some_end_it() {
    use Out::*;
    // Ctrl-C inside a sequence counts as typed; the sequence goes on.
    assert_eq!(decode(b"\x1b[1\x03A"), [Typed(0x03), key("1", b'A')]);
    assert_eq!(decode(b"\x1b]x\x03y\x07"), [Typed(0x03), Dropped]);
    // CAN cancels; ESC starts a new sequence; a byte above 0x7F ends one and is typed.
    assert_eq!(decode(b"\x1b[1\x18x"), [Dropped, Typed(b'x')]);
    assert_eq!(decode(b"\x1b[1\x1b[B"), [Dropped, key("", b'B')]);
    assert_eq!(decode(b"\x1b[1\xc3"), [Dropped, Typed(0xC3)]);
    // A string ended by an ESC that starts another sequence.
    assert_eq!(decode(b"\x1b]x\x1b[A"), [Dropped, key("", b'A')]);
    // DEL inside a sequence is ignored.
    assert_eq!(decode(b"\x1b[\x7fA"), [key("", b'A')]);
}

#[test]
fn reset_drops_the_sequence_under_way() {
    let mut d = KeyDecoder::default();
    assert!(!d.reset());
    d.byte(0x1B);
    d.byte(b']');
    assert!(d.in_sequence());
    assert!(d.reset(), "a sequence was under way");
    assert!(!d.in_sequence());
    assert_eq!(d.byte(b'+').key, Some(Key::Typed(b'+')));
}

/// One escape sequence, of every kind the decoder reads, with parameters or bodies of any
/// length (without control characters, which act inside a sequence as outside); with whether
/// it is a key (`Some(final byte)`) or is dropped.
pub(crate) fn escape_sequence() -> impl Strategy<Value = (Vec<u8>, Option<u8>)> {
    use prop::collection::vec;
    let csi = (
        prop::sample::select(vec![b'[', b'O']),
        vec(0x20u8..0x40, 0..200),
        0x40u8..0x7F,
    )
        .prop_map(|(intro, params, last)| {
            let key = (params.len() <= MAX_KEY_PARAMS).then_some(last);
            ([&[0x1B, intro][..], &params, &[last]].concat(), key)
        });
    let nf = (vec(0x20u8..0x30, 0..20), 0x30u8..0x7F)
        .prop_filter("no introducer right after ESC", |(i, last)| {
            !i.is_empty() || !b"[OPX]^_".contains(last)
        })
        .prop_map(|(i, last)| ([&[0x1B][..], &i, &[last]].concat(), None));
    let string = (
        prop::sample::select(b"PX]^_".to_vec()),
        vec(prop_oneof![0x20u8..0x7F, 0x80u8..=0xFF], 0..200),
        any::<bool>(),
    )
        .prop_map(|(intro, body, bel)| {
            let end: &[u8] = if bel { b"\x07" } else { b"\x1b\\" };
            ([&[0x1B, intro][..], &body, end].concat(), None)
        });
    prop_oneof![csi, nf, string]
}

/// Printable text or one escape sequence.
#[derive(Debug, Clone)]
pub(crate) enum Part {
    Text(String),
    /// A sequence's bytes, and its final byte when it is a key.
    Sequence(Vec<u8>, Option<u8>),
}

/// Printable text and escape sequences, in any order.
pub(crate) fn parts() -> impl Strategy<Value = Vec<Part>> {
    let part = prop_oneof![
        "[ -~]{0,8}".prop_map(Part::Text),
        escape_sequence().prop_map(|(s, key)| Part::Sequence(s, key)),
    ];
    prop::collection::vec(part, 0..12)
}

/// The bytes of `parts`.
pub(crate) fn bytes(parts: &[Part]) -> Vec<u8> {
    parts
        .iter()
        .flat_map(|p| match p {
            Part::Text(t) => t.as_bytes().to_vec(),
            Part::Sequence(s, _) => s.clone(),
        })
        .collect()
}

proptest! {
    /// Every byte of the text comes out typed, every sequence as exactly one key or one drop,
    /// and no byte of a sequence comes out typed.
    #[test]
    fn no_byte_of_an_escape_sequence_is_typed(parts in parts()) {
        let expected: Vec<Out> = parts
            .iter()
            .flat_map(|p| match p {
                Part::Text(t) => t.bytes().map(Out::Typed).collect::<Vec<_>>(),
                Part::Sequence(s, Some(last)) => {
                    let params = &s[2..s.len() - 1];
                    vec![Out::Key(String::from_utf8(params.to_vec()).unwrap(), *last)]
                }
                Part::Sequence(_, None) => vec![Out::Dropped],
            })
            .collect();
        prop_assert_eq!(decode(&bytes(&parts)), expected);
    }

    /// Over arbitrary bytes: ESC never comes out typed, and a byte comes out at most once.
    #[test]
    fn arbitrary_bytes_never_type_an_escape(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        let out = decode(&bytes);
        prop_assert!(!out.contains(&Out::Typed(0x1B)));
        let typed = out.iter().filter(|o| matches!(o, Out::Typed(_))).count();
        prop_assert!(typed <= bytes.len());
    }
}
