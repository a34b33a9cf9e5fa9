use super::{HttpLine, classify};
use crate::transport::hmi::words::{Line, parse_line};
use crate::transport::json::connection::tests::json_value;
use crate::transport::json::framing::{Decoder, Frame};
use mcm_shared::config::RobotConfig;
use mcm_shared::protocol::{COMMANDS, Command};
use proptest::prelude::*;

#[test]
fn request_lines_of_any_method_are_recognised() {
    for line in [
        "POST / HTTP/1.1",
        "GET /x HTTP/1.0",
        "OPTIONS * HTTP/1.1",
        "PROPFIND /a?b=c&d HTTP/1.1\r",
        "POST http://robot:18010/ HTTP/1.1",
        "BREW /pot HTTP/2",
        "get /lower-case-method HTTP/1.1",
    ] {
        assert_eq!(
            classify(line.as_bytes()),
            Some(HttpLine::Request),
            "{line:?}"
        );
    }
}

#[test]
fn header_lines_are_recognised() {
    for line in [
        "Host: robot:18010",
        "User-Agent: Mozilla/5.0 (X11; Linux x86_64)",
        "Content-Type:text/plain;charset=UTF-8",
        "sec-fetch-mode: no-cors\r",
        "X-Empty:",
    ] {
        assert_eq!(
            classify(line.as_bytes()),
            Some(HttpLine::Header),
            "{line:?}"
        );
    }
}

#[test]
fn commands_and_other_lines_are_not_http() {
    for line in [
        "",
        "\r",
        r#"{"command":"status"}"#,
        r#"  {"command":"calibrate","arguments":{"which":"ALL"}}"#,
        "status",
        "status detail",
        "calibrate which=WRIST",
        "move_axis 1 30 0.5",
        "authenticate pass:word",
        "HTTP/1.1 200 OK",
        "GET  / HTTP/1.1",
        "GET / HTTP/",
        "GET / HTTP/1.",
        "GET / http/1.1",
        "GET / HTTP/1.1 extra",
        ": no name",
        "two words: value",
        "\u{16}\u{3}\u{1}\u{2}\u{0}",
    ] {
        assert_eq!(classify(line.as_bytes()), None, "{line:?}");
    }
}

#[test]
fn no_example_of_any_command_is_http() {
    for def in COMMANDS {
        for example in def.examples {
            assert_eq!(classify(example.as_bytes()), None, "{example:?}");
        }
        assert_eq!(classify(def.name.as_bytes()), None, "{}", def.name);
    }
}

/// A word of an HMI line: anything typed without blanks.
fn word() -> impl Strategy<Value = String> {
    prop_oneof![
        "[!-~]{1,12}",
        Just("HTTP/1.1".to_string()),
        Just("/".to_string()),
        Just("*".to_string()),
        Just("x:".to_string()),
    ]
}

proptest! {
    #[test]
    fn no_line_the_json_parser_accepts_is_http(
        v in json_value(),
        name in prop::sample::select(mcm_shared::protocol::command_names().collect::<Vec<_>>()),
        blanks in "[ \t]{0,3}",
    ) {
        let cfg = RobotConfig::prob2_default();
        for value in [v.clone(), serde_json::json!({"command": name, "arguments": v}), serde_json::json!({"command": name})] {
            let line = format!("{blanks}{}", mcm_shared::protocol::json::to_ascii(&value));
            // What the JSON port takes as a command: a framed object that parses.
            let mut decoder = Decoder::new();
            decoder.extend(line.as_bytes());
            decoder.extend(b"\n");
            if let Some(Frame::Object(text)) = decoder.next_frame() {
                if Command::from_json(&text, &cfg).is_ok() {
                    prop_assert_eq!(classify(line.as_bytes()), None, "{}", line);
                }
                prop_assert_eq!(classify(text.as_bytes()), None, "{}", text);
            }
        }
    }

    #[test]
    fn no_line_the_hmi_accepts_is_http(
        name in prop::sample::select(
            crate::transport::hmi::session::completions(),
        ),
        words in prop::collection::vec(word(), 0..4),
    ) {
        let cfg = RobotConfig::prob2_default();
        let line = std::iter::once(name.to_string()).chain(words).collect::<Vec<_>>().join(" ");
        // `quit` takes any words: it ends the session as closing it does.
        if matches!(parse_line(&line, &cfg), Ok(l) if !matches!(l, Line::Empty | Line::Quit)) {
            prop_assert_eq!(classify(line.as_bytes()), None, "{}", line);
        }
    }
}
