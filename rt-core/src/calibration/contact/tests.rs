use super::*;

const P: ContactParams = ContactParams {
    threshold: 0.5,
    confirm_cycles: 6,
    min_lag: 0.01,
    stall_fraction: 0.5,
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

/// Steps `d` through `cycles` cycles of a search in the positive direction whose target moves
/// 0.01 per cycle; `axis(k, target)` gives the measured position and current. The cycle and
/// position of the contact, if one is confirmed.
fn search(
    d: &mut ContactDetector,
    p: &ContactParams,
    cycles: u32,
    axis: impl Fn(u32, f64) -> (f64, f64),
) -> Option<(u32, f64)> {
    (0..cycles).find_map(|k| {
        let target = 0.01 * f64::from(k);
        let (position, current) = axis(k, target);
        let sample = Sample {
            position,
            current,
            target,
        };
        d.step(p, 1.0, sample, true, 0.005).map(|at| (k, at))
    })
}

#[test]
fn the_swing_of_a_jolt_from_another_axis_is_no_contact() {
    // Another axis hits its stop: the arm throws this axis ahead of its target, then back,
    // ringing (the servo's current against the displacement); no stop anywhere.
    let swing = |k: u32| {
        let t = f64::from(k.saturating_sub(50));
        if k < 50 {
            0.0
        } else {
            0.1 * (-t / 40.0).exp() * (core::f64::consts::TAU * t / 24.0).sin()
        }
    };
    let mut d = settled(1.0);
    let found = search(&mut d, &P, 400, |k, target| {
        let ahead = swing(k);
        (target + ahead, 1.0 - 100.0 * ahead)
    });
    assert_eq!(found, None, "a contact in free air");
}

#[test]
fn a_load_change_while_the_axis_follows_leaves_no_stale_onset() {
    // At cycle 20 the load steps up by twice the threshold in the search direction (another
    // axis moved, gravity changed) while the axis goes on following; at cycle 200 a stop
    // holds it. The contact is where the stop holds it, not where the load changed.
    let mut d = settled(1.0);
    let stop = 0.01 * 200.0;
    let found = search(&mut d, &P, 400, |k, target| {
        let load = if k >= 20 { 2.0 } else { 1.0 };
        let position = target.min(stop);
        (position, load + 100.0 * (target - position))
    });
    let (k, at) = found.expect("the stop is found");
    assert!((at - stop).abs() < 0.015, "onset {at}, the stop at {stop}");
    assert!(k > 200, "confirmed at cycle {k}");
}
