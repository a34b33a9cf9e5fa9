use super::*;

const P: ContactParams = ContactParams {
    threshold: 0.5,
    confirm_cycles: 6,
    min_lag: 0.01,
    stall_fraction: 0.5,
    track_armed: true,
};

fn settled(current: f64) -> ContactDetector {
    let mut d = ContactDetector::new(current);
    for _ in 0..100 {
        d.track(current, 0.005);
    }
    d
}

#[test]
fn a_stall_with_the_current_up_is_a_contact_at_its_onset() {
    let mut d = settled(1.0);
    let mut found = None;
    for k in 0..20 {
        let target = 0.01 * f64::from(k);
        // The axis stops at 0.05 while its target moves on; the current rises.
        let position = target.min(0.05);
        let current = 1.0 + 100.0 * (target - position);
        if let Some(at) = d.step(
            &P,
            1.0,
            Sample {
                position,
                current,
                target,
            },
            true,
            0.005,
        ) {
            found = Some((k, at));
            break;
        }
    }
    let (k, at) = found.expect("contact");
    assert!((at - 0.05).abs() < 1e-12, "onset {at}");
    assert!(k <= 6 + 6, "confirmed within the run: cycle {k}");
}

#[test]
fn current_against_the_search_direction_is_no_contact() {
    let mut d = settled(1.0);
    for k in 0..50 {
        let target = 0.01 * f64::from(k);
        let position = target.min(0.05);
        let current = 1.0 - 100.0 * (target - position);
        assert_eq!(
            d.step(
                &P,
                1.0,
                Sample {
                    position,
                    current,
                    target
                },
                true,
                0.005
            ),
            None
        );
    }
}

#[test]
fn a_current_departure_while_the_axis_follows_is_no_contact() {
    let mut d = settled(1.0);
    for k in 0..200 {
        let target = 0.01 * f64::from(k);
        let position = target - 0.02;
        assert_eq!(
            d.step(
                &P,
                1.0,
                Sample {
                    position,
                    current: 5.0,
                    target
                },
                true,
                0.005
            ),
            None
        );
    }
}

#[test]
fn nothing_before_the_baseline_settles_or_while_unarmed() {
    let mut d = ContactDetector::new(1.0);
    assert!(!d.settled());
    for armed in [false, true] {
        d.restart();
        for _ in 0..(SETTLE / 0.005) as u32 - 1 {
            assert_eq!(
                d.step(
                    &P,
                    1.0,
                    Sample {
                        position: 0.0,
                        current: 9.0,
                        target: 1.0
                    },
                    armed,
                    0.005
                ),
                None
            );
        }
    }
}
