//! The line editor key by key, and property tests of its escape-sequence parsing over
//! arbitrary bytes.

use super::*;
use proptest::prelude::*;

const WORDS: &[&str] = &["status", "sleep", "sim", "help", "hold"];

fn run(e: &mut Editor, bytes: &[u8], echo: bool) -> (Vec<Action>, String) {
    let mut out = Vec::new();
    let actions = bytes
        .iter()
        .map(|b| match *b {
            b'\n' => Input::Enter,
            b => Input::Byte(b),
        })
        .filter_map(|i| e.feed(i, echo, &mut out))
        .collect();
    (actions, String::from_utf8_lossy(&out).into_owned())
}

fn line(s: &str) -> Action {
    Action::Line(s.to_string())
}

/// Feed `bytes` (no Enter among them): the line is then `text`; Enter runs it with echo, and
/// refuses it without echo (it held an escape sequence).
fn then_enter(e: &mut Editor, bytes: &[u8], echo: bool, text: &str) {
    let (a, _) = run(e, bytes, echo);
    assert!(a.is_empty(), "{a:?}");
    assert_eq!(e.text(), text, "echo {echo}");
    let (a, _) = run(e, b"\n", echo);
    let expected = if echo { line(text) } else { Action::Escaped };
    assert_eq!(a, [expected], "echo {echo}");
}

#[test]
fn typing_echo_and_backspace() {
    let mut e = Editor::new(100, WORDS.to_vec());
    let (a, out) = run(&mut e, b"holx\x7Fd\n", true);
    assert_eq!(a, [line("hold")]);
    assert_eq!(out, "holx\x08 \x08d\r\n");
    // Without echo nothing is written back; Backspace still edits.
    let (a, out) = run(&mut e, b"statux\x08s\n", false);
    assert_eq!(a, [line("status")]);
    assert!(out.is_empty());
}

#[test]
fn cursor_movement_and_editing_keys() {
    let mut e = Editor::new(100, WORDS.to_vec());
    // "move 1": Left twice, insert "_axis"... via Home/End and arrows.
    let (a, _) = run(&mut e, b"ove_axis\x1b[Hm\x1b[F 1 30\n", true);
    assert_eq!(a, [line("move_axis 1 30")]);
    let (a, _) = run(&mut e, b"abc\x1b[D\x1b[D\x1b[3~\n", true);
    assert_eq!(a, [line("ac")]);
    let (a, _) = run(&mut e, b"one two\x17three\n", true);
    assert_eq!(a, [line("one three")]);
    let (a, _) = run(&mut e, b"abcdef\x01\x06\x06\x0b\n", true);
    assert_eq!(a, [line("ab")]);
    let (a, _) = run(&mut e, b"junk\x15ok\n", true);
    assert_eq!(a, [line("ok")]);
    // Unknown escape sequences never reach the line.
    let (a, _) = run(&mut e, b"a\x1b[1;5Cb\x1bOPc\n", true);
    assert_eq!(a, [line("abc")]);
    let (a, _) = run(&mut e, b"x\x1b[A", false);
    assert!(a.is_empty());
    assert_eq!(e.text(), "x", "no history without echo");
    let (a, _) = run(&mut e, b"\n", false);
    assert_eq!(a, [Action::Escaped], "the line held a key");
}

#[test]
fn a_line_with_the_secret_is_not_kept_in_the_history() {
    let mut e = Editor::new(200, WORDS.to_vec());
    run(&mut e, b"status\nauthenticate hunter2\n", true);
    run(
        &mut e,
        b"{\"command\":\"authenticate\",\"arguments\":{\"secret\":\"x\"}}\n",
        true,
    );
    let (a, _) = run(&mut e, b"\x1b[A\n", true);
    assert_eq!(a, [line("status")]);
}

#[test]
fn history() {
    let mut e = Editor::new(100, WORDS.to_vec());
    run(&mut e, b"first\nsecond\n", true);
    let (a, _) = run(&mut e, b"\x1b[A\n", true);
    assert_eq!(a, [line("second")]);
    let (a, _) = run(&mut e, b"typed\x1b[A\x1b[A\x1b[A\n", true);
    assert_eq!(a, [line("first")], "Up stops at the oldest line");
    // History is now first, second, first.
    let (a, _) = run(&mut e, b"typed\x1b[A\x1b[A\x1b[A\x1b[B\n", true);
    assert_eq!(a, [line("second")], "Down walks back towards the newest");
    let (a, _) = run(&mut e, b"typed\x10\x0e\n", true);
    assert_eq!(
        a,
        [line("typed")],
        "Down past the newest restores the typed line"
    );
}

#[test]
fn ctrl_c_and_ctrl_d() {
    let mut e = Editor::new(100, WORDS.to_vec());
    let (a, out) = run(&mut e, b"half a line\x03", true);
    assert_eq!(a, [Action::Interrupt]);
    assert!(out.ends_with("line"), "at the end already: no movement");
    let (a, out) = run(&mut e, b"abc\x01\x03", true);
    assert_eq!(a, [Action::Interrupt]);
    assert!(
        out.ends_with("\x1b[3C"),
        "cursor to the end before ^C: {out:?}"
    );
    assert_eq!(e.text(), "");
    let (a, _) = run(&mut e, b"ab\x01\x04\n", true);
    assert_eq!(a, [line("b")], "Ctrl-D inside a line deletes");
    let (a, _) = run(&mut e, b"\x04", true);
    assert_eq!(a, [Action::Eof]);
    let mut out = Vec::new();
    assert_eq!(
        e.feed(Input::Interrupt, false, &mut out),
        Some(Action::Interrupt)
    );
    assert_eq!(e.feed(Input::EndOfFile, false, &mut out), Some(Action::Eof));
}

#[test]
fn completion() {
    let mut e = Editor::new(100, WORDS.to_vec());
    let (a, _) = run(&mut e, b"sta\t\n", true);
    assert_eq!(a, [line("status ")]);
    let (a, out) = run(&mut e, b"s\t", true);
    assert!(a.is_empty());
    assert!(out.contains("status  sleep  sim"), "{out:?}");
    let (a, _) = run(&mut e, b"\x15help ho\t\n", true);
    assert_eq!(a, [line("help hold ")]);
    let (a, _) = run(&mut e, b"st\tx\n", false);
    assert_eq!(a, [line("st x")], "Tab is a space without echo");
}

#[test]
fn utf8_characters() {
    let mut e = Editor::new(100, WORDS.to_vec());
    let (a, out) = run(&mut e, "a\u{e4}\u{20ac}".as_bytes(), true);
    assert!(a.is_empty());
    assert_eq!(out, "a??", "non-ASCII characters are echoed as ASCII");
    let (a, _) = run(&mut e, b"\x7F\n", true);
    assert_eq!(a, [line("a\u{e4}")]);
    let (a, _) = run(&mut e, b"x\xFF\xC3y\n", true);
    assert_eq!(a, [line("xy")], "invalid UTF-8 is dropped");
}

#[test]
fn long_lines_are_dropped_with_bounded_memory() {
    let mut e = Editor::new(10, WORDS.to_vec());
    let (a, _) = run(&mut e, b"0123456789abcdef", true);
    assert!(a.is_empty());
    assert!(e.line.capacity() <= 16 && e.text().is_empty());
    let (a, _) = run(&mut e, b"\nok\n", true);
    assert_eq!(a, [Action::TooLong { limit: 10 }, line("ok")]);
    let (a, _) = run(&mut e, b"0123456789\n", true);
    assert_eq!(a, [line("0123456789")], "exactly the limit is fine");
    let (a, _) = run(&mut e, b"0123456789a\n", true);
    assert_eq!(
        a,
        [Action::TooLong { limit: 10 }],
        "one byte more is refused"
    );
    // The limit counts UTF-8 bytes: 9 + a 2-byte character is one too many.
    let (a, _) = run(&mut e, "012345678\u{e9}\n".as_bytes(), true);
    assert_eq!(a, [Action::TooLong { limit: 10 }]);
}

#[test]
fn history_is_bounded() {
    let mut e = Editor::new(100, WORDS.to_vec());
    for i in 0..(HISTORY_LINES + 20) {
        run(&mut e, format!("line {i}\n").as_bytes(), true);
    }
    assert_eq!(e.history.len(), HISTORY_LINES);
    assert_eq!(e.history.front().unwrap(), "line 20");
}

#[test]
fn escape_sequences_of_any_length_are_read_to_their_end() {
    for echo in [false, true] {
        let mut e = Editor::new(100, WORDS.to_vec());
        // A CSI with long parameters (a terminal's report, a modified key) is one sequence.
        let long = format!("a\x1b[{}Db", "1;".repeat(40));
        then_enter(&mut e, long.as_bytes(), echo, "ab");
        // A window-title report (OSC, ended by BEL or by ST) and a charset designation.
        then_enter(
            &mut e,
            b"a\x1b]0;a title\x07b\x1b]2;x\x1b\\c\x1b(Bd",
            echo,
            "abcd",
        );
        // ESC and a key (Alt-x) is a sequence too: dropped whole.
        then_enter(&mut e, b"a\x1bxb", echo, "ab");
    }
}

/// Without echo (`nc`) an escape sequence cannot be edited: dropping it would run a shorter
/// line than the person typed (`move_axis 1 3` for `30`), so Enter refuses the line instead.
#[test]
fn without_echo_a_line_that_held_an_escape_sequence_is_refused_not_run_shortened() {
    let mut e = Editor::new(100, WORDS.to_vec());
    for typed in [
        &b"move_axis 1 3\x1b[D0\n"[..],
        b"move_axis 1 3\x1bx0\n",
        b"move_axis 1 3\x1b]0;t\x070\n",
        // A control string swallows everything up to Enter.
        b"move_axis 1 3\x1bP0\n",
        b"move_axis 1 3\x1b_0\n",
    ] {
        let (a, _) = run(&mut e, typed, false);
        assert_eq!(a, [Action::Escaped], "{:?}", String::from_utf8_lossy(typed));
    }
    // The refusal is not remembered, and the next line runs.
    let (a, _) = run(&mut e, b"move_axis 1 30\n", false);
    assert_eq!(a, [line("move_axis 1 30")]);
    // Ctrl-C drops the line and what it held.
    let (a, _) = run(&mut e, b"a\x1b[D\x03b\n", false);
    assert_eq!(a, [Action::Interrupt, line("b")]);
    // With echo the person sees the line as edited: it runs.
    let (a, _) = run(&mut e, b"move_axis 1 3\x1b[D0\x1b[F\n", true);
    assert_eq!(a, [line("move_axis 1 03")]);
}

#[test]
fn a_control_inside_a_sequence_still_acts_and_memory_stays_bounded() {
    let mut e = Editor::new(100, WORDS.to_vec());
    // Ctrl-C in the middle of a sequence interrupts.
    let (a, _) = run(&mut e, b"abc\x1b[12\x03", true);
    assert_eq!(a, [Action::Interrupt]);
    // CAN cancels a sequence; what follows is typed.
    let (a, _) = run(&mut e, b"\x1b[12\x18x\n", true);
    assert_eq!(a, [line("x")]);
    // A byte above 0x7F ends a sequence and counts as typed.
    then_enter(&mut e, "\x1b[1\u{e9}".as_bytes(), false, "\u{e9}");
    // A control string that never ends takes every byte, and nothing is kept of it.
    let mut e = Editor::new(100, WORDS.to_vec());
    let mut flood = b"\x1b]".to_vec();
    flood.extend(std::iter::repeat_n(b'x', 200_000));
    let (a, _) = run(&mut e, &flood, true);
    assert!(a.is_empty());
    assert_eq!(e.text(), "");
    assert_eq!(e.line.capacity(), 0, "nothing of the string was kept");
    // Enter ends it all.
    let (a, _) = run(&mut e, b"\nok\n", true);
    assert_eq!(a, [line(""), line("ok")]);
}

/// Printable text and escape sequences (of every kind, [`crate::transport::hmi::keys::tests`]),
/// in any order; the text alone.
fn text_and_sequences() -> impl Strategy<Value = (Vec<u8>, String)> {
    use crate::transport::hmi::keys::tests::{Part, bytes, parts};
    parts().prop_map(|parts| {
        let text = parts
            .iter()
            .map(|p| match p {
                Part::Text(t) => t.as_str(),
                Part::Sequence(..) => "",
            })
            .collect();
        (bytes(&parts), text)
    })
}

fn sorted(s: &str) -> Vec<char> {
    let mut v: Vec<char> = s.chars().collect();
    v.sort_unstable();
    v
}

proptest! {
    /// Without echo no key acts: the line is exactly the text between the sequences.
    #[test]
    fn no_byte_of_an_escape_sequence_reaches_the_line((bytes, text) in text_and_sequences()) {
        let mut e = Editor::new(100_000, WORDS.to_vec());
        let (a, _) = run(&mut e, &bytes, false);
        prop_assert!(a.is_empty());
        prop_assert_eq!(e.text(), text);
    }

    /// With echo, editing keys may move the cursor or delete a character, but the line holds
    /// only characters of the text.
    #[test]
    fn with_echo_the_line_holds_only_typed_characters((bytes, text) in text_and_sequences()) {
        let mut e = Editor::new(100_000, WORDS.to_vec());
        run(&mut e, &bytes, true);
        let (mut line, mut typed) = (sorted(&e.text()).into_iter(), sorted(&text).into_iter());
        // `line` is a sub-multiset of `typed`.
        for c in line.by_ref() {
            prop_assert!(typed.any(|t| t == c), "{:?} is no typed character: {:?} from {:?}", c, e.text(), text);
        }
    }

    /// Over arbitrary bytes: no control character ever reaches the line, and the editor keeps
    /// no more than the line itself.
    #[test]
    fn arbitrary_bytes_leave_no_control_character_in_the_line(
        bytes in prop::collection::vec(any::<u8>(), 0..600),
        echo in any::<bool>(),
    ) {
        let mut e = Editor::new(100, WORDS.to_vec());
        let bytes: Vec<u8> = bytes.into_iter().filter(|b| *b != b'\n').collect();
        run(&mut e, &bytes, echo);
        let text = e.text();
        prop_assert!(!text.chars().any(char::is_control), "{:?}", text);
        prop_assert!(e.line.capacity() <= 256, "{}", e.line.capacity());
    }
}

/// Tab completes the one word that starts with what was typed, followed by a space.
#[test]
fn tab_completes_a_unique_command() {
    let mut e = Editor::new(100, vec!["status", "sleep"]);
    let mut echo = Vec::new();
    for b in *b"sta\t" {
        e.feed(Input::Byte(b), true, &mut echo);
    }
    assert_eq!(
        e.feed(Input::Enter, true, &mut echo),
        Some(Action::Line("status ".into()))
    );
}
