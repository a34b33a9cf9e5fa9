//! Property tests of the HMI's line path over arbitrary bytes: telnet -> editor -> words ->
//! the text a session writes. No panic, one answer per Enter, and only ASCII is written
//! (telnet negotiation answers aside, which are protocol bytes, not text).

use super::editor::{Action, Editor};
use super::session::{completions, terminal_text};
use super::telnet::{Input, Telnet};
use super::words::{Line, LineError, parse_line};
use super::{MAX_LINE_BYTES, help, render};
use crate::command::result;
use mcm_shared::config::RobotConfig;
use proptest::prelude::*;

/// Run `bytes` through one session's line path; returns (answers, Enter count).
fn session_path(bytes: &[u8], echo_agreed: bool, max_bytes: usize) -> (usize, usize) {
    let cfg = RobotConfig::prob2_default();
    let mut telnet = Telnet::new();
    let mut editor = Editor::new(max_bytes, completions());
    editor.set_prompt("mcm HOLD> ");
    let (mut inputs, mut replies) = (Vec::new(), Vec::new());
    if echo_agreed {
        telnet.feed(&[255, 253, 1], &mut inputs, &mut replies);
    }
    telnet.feed(bytes, &mut inputs, &mut replies);
    let (mut answers, mut enters) = (0, 0);
    for input in inputs {
        enters += usize::from(input == Input::Enter);
        let mut out = Vec::new();
        let action = editor.feed(input, telnet.server_echoes(), &mut out);
        let text = match action.clone() {
            None | Some(Action::Interrupt | Action::Eof) => String::new(),
            Some(Action::TooLong { limit }) => format!("line longer than {limit} bytes"),
            Some(Action::Escaped) => "the line held an escape sequence".to_string(),
            Some(Action::Line(line)) => match parse_line(&line, &cfg) {
                Ok(Line::Help(Some(t))) => help::topic(&t, &cfg),
                Ok(Line::Help(None)) => help::overview(),
                Ok(_) => String::new(),
                Err(LineError::Json(e)) => render::pretty(&result::error(e.code(), e.to_string())),
                Err(e) => render::line_error(&e),
            },
        };
        if input == Input::Enter {
            assert!(
                matches!(
                    action,
                    Some(Action::Line(_) | Action::TooLong { .. } | Action::Escaped)
                ),
                "Enter gives a line: {action:?}"
            );
            answers += 1;
        }
        terminal_text(&text, &mut out);
        assert!(out.is_ascii(), "{:?}", String::from_utf8_lossy(&out));
    }
    (answers, enters)
}

/// A few words the parser knows, to reach deeper than random bytes do.
const WORDS: &[&str] = &[
    "move_axis 1 30 vf=0.5",
    "move_all 0 10 20 0 0 0",
    "help move_all",
    "{\"command\":\"status\"}",
    "calibrate which=WRIST",
    "pvt_points [{\"t\":0.1}]",
    "\t",
    "\u{e9}\u{1F600}",
    "\x1b[D\x1b[3~",
    "\"",
    "{",
];

proptest! {
    #[test]
    fn arbitrary_bytes_give_one_ascii_answer_per_enter(
        bytes in prop::collection::vec(any::<u8>(), 0..1024),
        echo in any::<bool>(),
    ) {
        let (answers, enters) = session_path(&bytes, echo, MAX_LINE_BYTES);
        prop_assert_eq!(answers, enters);
    }

    #[test]
    fn arbitrary_json_values_give_one_ascii_answer(
        v in crate::transport::json::connection::tests::json_value(),
        command in prop::sample::select(mcm_shared::protocol::command_names().collect::<Vec<_>>()),
        escaped in any::<bool>(),
    ) {
        // As a JSON line (`{...}`) and as the arguments of a command; escaped (`\uXXXX`) or
        // raw UTF-8, which people type.
        for value in [v.clone(), serde_json::json!({"command": command, "arguments": v})] {
            let text = if escaped {
                mcm_shared::protocol::json::to_ascii(&value)
            } else {
                value.to_string()
            };
            let line = format!("{}\r\n", text.replace(['\r', '\n'], " "));
            prop_assert_eq!(session_path(line.as_bytes(), true, MAX_LINE_BYTES), (1, 1));
        }
    }

    #[test]
    fn mixed_words_and_bytes(
        parts in prop::collection::vec(
            prop_oneof![
                prop::sample::select(WORDS).prop_map(|w| w.as_bytes().to_vec()),
                prop::collection::vec(any::<u8>(), 0..8),
                Just(b"\r\n".to_vec()),
            ],
            0..24,
        ),
        echo in any::<bool>(),
        max_bytes in 1usize..64,
    ) {
        let bytes = parts.concat();
        let (answers, enters) = session_path(&bytes, echo, max_bytes);
        prop_assert_eq!(answers, enters);
    }
}

#[test]
fn the_line_that_panicked_is_answered_in_ascii() {
    let line = format!(
        "{{\"command\":\"calibrate\",\"arguments\":{{\"which\":\"{}\u{e9}\"}}}}\r\n",
        "a".repeat(58)
    );
    assert_eq!(session_path(line.as_bytes(), true, MAX_LINE_BYTES), (1, 1));
    // Completion after `help` with a multi-byte character before it.
    assert_eq!(
        session_path("\u{3000}help \t\r\n".as_bytes(), true, 100),
        (1, 1)
    );
}
