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
    assert_eq!(keys(b" w\x1b[H"), [Stop, Stop, Stop]);
    assert_eq!(
        keys(b"xyzXYZfF"),
        [
            Choose(TcpDirection::Along(0)),
            Choose(TcpDirection::Along(1)),
            Choose(TcpDirection::Along(2)),
            Choose(TcpDirection::About(0)),
            Choose(TcpDirection::About(1)),
            Choose(TcpDirection::About(2)),
            Frame,
            Frame
        ]
    );
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
                            b'x' => JogKey::Choose(TcpDirection::Along(0)),
                            b'y' => JogKey::Choose(TcpDirection::Along(1)),
                            b'z' => JogKey::Choose(TcpDirection::Along(2)),
                            b'X' => JogKey::Choose(TcpDirection::About(0)),
                            b'Y' => JogKey::Choose(TcpDirection::About(1)),
                            b'Z' => JogKey::Choose(TcpDirection::About(2)),
                            b'f' | b'F' => JogKey::Frame,
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

#[test]
fn a_tcp_jog_sends_its_direction_in_metres_or_degrees_in_its_frame() {
    let mut jog = TcpJog {
        direction: TcpDirection::Along(1),
        frame: CartesianFrame::Base,
        linear_mm_s: 25.0,
        angular_deg_s: 15.0,
    };
    let v = jog.velocity(-1);
    assert_eq!(
        (v.linear_m_s, v.angular_deg_s, v.frame),
        ([0.0, -0.025, 0.0], [0.0; 3], CartesianFrame::Base)
    );
    assert_eq!(jog.speed(), (25.0, "mm/s"));
    jog.direction = TcpDirection::About(2);
    jog.toggle_frame();
    let v = jog.velocity(1);
    assert_eq!(
        (v.linear_m_s, v.angular_deg_s, v.frame),
        ([0.0; 3], [0.0, 0.0, 15.0], CartesianFrame::Tool)
    );
    assert_eq!(jog.velocity(0).angular_deg_s, [0.0; 3]);
    assert_eq!(jog.speed(), (15.0, "deg/s"));
    jog.toggle_frame();
    assert_eq!(jog.frame, CartesianFrame::Base);

    assert_eq!(check_tcp_speed(TcpDirection::Along(0), 1000.0), Ok(1000.0));
    let e = check_tcp_speed(TcpDirection::Along(0), 1000.5).unwrap_err();
    assert!(
        e.contains("speed = 1000.5") && e.contains("at most 1000 mm/s"),
        "{e}"
    );
    let e = check_tcp_speed(TcpDirection::About(0), -1.0).unwrap_err();
    assert!(
        e.contains("above 0") && e.contains("at most 180 deg/s"),
        "{e}"
    );
    for w in ["x", "y", "z", "rx", "ry", "rz"] {
        assert_eq!(TcpDirection::from_word(w).map(TcpDirection::word), Some(w));
    }
    assert_eq!(TcpDirection::from_word("RX"), Some(TcpDirection::About(0)));
    assert_eq!(TcpDirection::from_word("w"), None);
}

#[test]
fn the_tcp_status_line_shows_the_pose_the_direction_and_the_frame() {
    let jog = TcpJog {
        direction: TcpDirection::About(0),
        frame: CartesianFrame::Tool,
        linear_mm_s: 20.0,
        angular_deg_s: 10.0,
    };
    let mut s = StateSample::default();
    let line = tcp_status_line(&jog, &s, 0);
    assert!(line.contains("no TCP pose"), "{line}");
    s.flags |= STATE_CARTESIAN;
    s.cartesian.position = [0.4, -0.05, 0.5];
    s.cartesian.orientation = [1.0, 0.0, 0.0, 0.0];
    let line = tcp_status_line(&jog, &s, 1);
    assert!(
        line.contains("about X tool frame")
            && line.contains("400.00    -50.00    500.00 mm")
            && line.contains("180.000")
            && line.contains(">>>")
            && line.contains("(10 deg/s)"),
        "{line}"
    );
}

/// `help jog` types the TCP's default speeds and their limits as words: they must be the
/// constants the jog uses and the argument table's ranges `set_cartesian_velocity` takes.
#[test]
fn the_help_states_the_tcp_jogs_defaults_and_limits() {
    use mcm_shared::ranges::Arg;
    for (default, arg, per) in [
        (DEFAULT_TCP_SPEED_MM_S, Arg::Linear, 1000.0),
        (DEFAULT_TCP_TURN_DEG_S, Arg::Angular, 1.0),
    ] {
        let want = format!(
            "(default {default}, at most {})",
            arg.fixed_bounds().1 * per
        );
        assert!(HELP.contains(&want), "help jog lacks {want:?}:\n{HELP}");
    }
}
