//! What a session writes to the terminal: [`terminal_text`] keeps the HMI's own colours and
//! shows every other control character visibly, whatever the text; text from outside the HMI
//! (names from the configuration) shows even those ([`render::visible`]).

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

/// A robot or axis name holding one of the HMI's own colours and a line end is shown as it
/// is: it cannot colour the terminal, nor start a line that looks like the HMI's.
#[test]
fn names_from_the_configuration_show_their_control_characters() {
    use mcm_shared::mode::Mode;
    use mcm_shared::sample::StateSample;
    let mut cfg = mcm_shared::config::RobotConfig::prob2_default();
    cfg.robot.name = format!("P-Rob2{}\nmode:  HOLD - fine", render::RED);
    cfg.axes[2].name = format!("elb{}\now", render::GREEN);
    let banner = shown(&render::banner(&cfg, None, "x"));
    assert!(
        banner.contains("\r\nrobot: P-Rob2^[[1;31m^Jmode:  HOLD - fine\r\n"),
        "{banner:?}"
    );
    assert!(!banner.contains(render::RED), "{banner:?}");
    assert_eq!(banner.matches("\r\n").count(), 4, "{banner:?}");
    let state = StateSample {
        mode: Mode::Off.to_wire(),
        ..StateSample::default()
    };
    let status = crate::command::result::status_answer("status", &state, false);
    let table = shown(&render::answer("status", &status, &cfg, None));
    let row = table
        .split("\r\n")
        .find(|l| l.trim_start().starts_with('3'))
        .expect("a row for axis 3");
    assert!(row.contains("elb^[[32m^Jow"), "{table:?}");
    assert!(!table.contains(render::GREEN), "{table:?}");
    // The line that refuses a session: the same rules.
    assert_eq!(
        crate::transport::hmi::hmi_line("a\x1b[1;31mb\nc"),
        "MCM HMI: a^[[1;31mb^Jc\r\n"
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
