use super::*;

fn keys(bytes: &[u8]) -> Vec<JogKey> {
    let mut d = KeyDecoder::default();
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
    let mut d = KeyDecoder::default();
    assert_eq!(d.feed(Input::Interrupt), Some(Quit));
    assert_eq!(d.feed(Input::Enter), Some(Stop));
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
