//! What a session writes to the terminal: [`terminal_text`] keeps the HMI's own colours and
//! shows every other control character visibly, whatever the text.

use super::*;
use proptest::prelude::*;

fn shown(text: &str) -> String {
    let mut out = Vec::new();
    terminal_text(text, &mut out);
    String::from_utf8(out).expect("ASCII")
}

#[test]
fn own_colours_pass_and_other_control_characters_are_shown_visibly() {
    let red = format!("{}error:{} no\n", render::RED, render::RESET);
    assert_eq!(
        shown(&red),
        format!("{}error:{} no\r\n", render::RED, render::RESET)
    );
    assert_eq!(shown("robot: P-Rob2\x1b[2J\n"), "robot: P-Rob2^[[2J\r\n");
    assert_eq!(shown("t\x1b]0;x\x07\r\t\x7f\0"), "t^[]0;x^G^M^I^?^@");
    // A colour cut short, or one the HMI does not use, is not a colour.
    assert_eq!(shown("\x1b[1;3"), "^[[1;3");
    assert_eq!(shown("\x1b[31m"), "^[[31m");
    assert_eq!(
        shown("caf\u{e9} \u{9b}2J"),
        "caf? ?2J",
        "C1 controls are non-ASCII"
    );
}

proptest! {
    #[test]
    fn no_control_character_but_line_ends_and_own_colours_reaches_the_terminal(
        text in prop::collection::vec(
            prop_oneof![
                any::<char>().prop_map(String::from),
                prop::sample::select(OWN_COLOURS.to_vec()).prop_map(String::from),
                prop::sample::select(vec!["\n", "\r", "\x1b", "\x1b[", "\x07"]).prop_map(String::from),
            ],
            0..40,
        ).prop_map(|parts| parts.concat())
    ) {
        let out = shown(&text);
        let mut rest = out.as_str();
        while let Some(c) = rest.chars().next() {
            if let Some(colour) = OWN_COLOURS.iter().find(|c| rest.starts_with(**c)) {
                rest = &rest[colour.len()..];
                continue;
            }
            if rest.starts_with("\r\n") {
                rest = &rest[2..];
                continue;
            }
            prop_assert!(!c.is_ascii_control(), "{c:?} in {out:?} (from {text:?})");
            rest = &rest[c.len_utf8()..];
        }
        if !text.chars().any(|c| c.is_control()) {
            prop_assert_eq!(out, render::ascii(&text).into_owned(), "plain text is unchanged");
        }
    }
}
