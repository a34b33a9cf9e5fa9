//! The jog screen's keys, held-key timing and speeds.

use super::*;
use crate::transport::hmi::keys::tests::{Part, parts};
use proptest::prelude::*;

fn keys(bytes: &[u8]) -> Vec<JogKey> {
    let mut d = JogKeys::default();
    bytes
        .iter()
        .filter_map(|b| d.feed(Input::Byte(*b)))
        .collect()
}

#[test]
fn keys_and_arrows() {
    use JogKey::*;
    assert_eq!(keys(b"+-=_"), [Plus, Minus, Plus, Minus]);
    assert_eq!(
        keys(b"\x1b[A\x1b[B\x1b[C\x1b[D"),
        [Plus, Minus, Plus, Minus]
    );
    assert_eq!(keys(b"\x1bOA\x1b[1;5C"), [Plus, Plus]);
    assert_eq!(keys(b"qQ\x03\x04"), [Quit, Quit, Quit, Quit]);
    assert_eq!(keys(b" x\x1b[H"), [Stop, Stop, Stop]);
    let mut d = JogKeys::default();
    assert_eq!(d.feed(Input::Interrupt), Some(Quit));
    assert_eq!(d.feed(Input::Enter), Some(Stop));
}

/// A window-title string (OSC) holding `+` mid-jog is one other key: it stops, never moves.
#[test]
fn a_title_string_is_no_jog_key() {
    use JogKey::*;
    assert_eq!(keys(b"\x1b]0;+x\x07"), [Stop]);
    assert_eq!(keys(b"+\x1b]0;+x\x1b\\-"), [Plus, Stop, Minus]);
    // Alt-+ and a charset designation are no `+` either.
    assert_eq!(keys(b"\x1b+\x1b(B"), [Stop, Stop]);
}

proptest! {
    /// Every character of the text is a key of its own; every escape sequence is exactly one
    /// key, `Plus` or `Minus` only for an arrow: no byte of a sequence is a jog key.
    #[test]
    fn no_byte_of_an_escape_sequence_is_a_jog_key(parts in parts()) {
        let mut d = JogKeys::default();
        for part in parts {
            match part {
                Part::Text(t) => {
                    for b in t.bytes() {
                        let key = d.feed(Input::Byte(b));
                        let expected = match b {
                            b'+' | b'=' => JogKey::Plus,
                            b'-' | b'_' => JogKey::Minus,
                            b'q' | b'Q' => JogKey::Quit,
                            _ => JogKey::Stop,
                        };
                        prop_assert_eq!(key, Some(expected));
                    }
                }
                Part::Sequence(bytes, key) => {
                    let got: Vec<JogKey> = bytes.iter().filter_map(|b| d.feed(Input::Byte(*b))).collect();
                    let expected = match key {
                        Some(b'A' | b'C') => JogKey::Plus,
                        Some(b'B' | b'D') => JogKey::Minus,
                        _ => JogKey::Stop,
                    };
                    prop_assert_eq!(got, vec![expected], "{:?}", bytes);
                }
            }
        }
    }
}

#[test]
fn a_held_key_moves_until_its_repeats_stop() {
    let t0 = Instant::now();
    let ms = |n| t0 + Duration::from_millis(n);
    let mut h = Held::default();
    assert_eq!(h.direction(t0), 0);
    h.press(1, t0);
    // Before the terminal's auto-repeat starts, the key counts as held.
    assert_eq!(h.direction(ms(500)), 1);
    // Repeats every 33 ms.
    let mut t = 600;
    while t < 1500 {
        h.press(1, ms(t));
        assert_eq!(h.direction(ms(t + 20)), 1);
        t += 33;
    }
    // Let go: stopped within the repeat gap.
    assert_eq!(h.direction(ms(t + 150)), 1);
    assert_eq!(h.direction(ms(t + 250)), 0);
    // A single press without repeats stops after the first gap.
    h.press(-1, ms(5000));
    assert_eq!(h.direction(ms(5600)), -1);
    assert_eq!(h.direction(ms(5800)), 0);
    // The other direction, or another key, takes over at once.
    h.press(1, ms(6000));
    h.press(-1, ms(6010));
    assert_eq!(h.direction(ms(6020)), -1);
    h.stop();
    assert_eq!(h.direction(ms(6030)), 0);
}

#[test]
fn speeds_and_velocities() {
    let cfg = RobotConfig::prob2_default();
    let axis = Axis::new(2).unwrap();
    assert_eq!(check_speed(&cfg, axis, 90.0), Ok(90.0));
    let e = check_speed(&cfg, axis, 91.0).unwrap_err();
    assert!(e.contains("speed = 91") && e.contains("at most 90"), "{e}");
    assert!(check_speed(&cfg, axis, 0.0).is_err());
    assert_eq!(velocities(axis, 5.0, -1), [0.0, -5.0, 0.0, 0.0, 0.0, 0.0]);
    let line = status_line(axis, "shoulder", 12.3456, -5.0, 5.0, -1);
    assert!(
        line.contains("12.346 deg") && line.contains("<<<"),
        "{line}"
    );
}
