//! Unit and property tests of the velocity ramp: limits respected, target reached, a joint
//! driven into a limit at rest before it with the braking-distance check passing every cycle.

use super::super::ramp_limits;
use super::*;
use crate::params::JointParams;
use crate::safety::{SafetyParams, check_braking};
use mcm_shared::config::RobotConfig;
use proptest::prelude::*;

const DT: f64 = 0.005;
/// Rounding allowance of the limit checks.
const EPS: f64 = 1e-9;

fn prob2() -> (JointParams, SafetyParams) {
    let cfg = RobotConfig::prob2_default();
    (
        JointParams::from_config(&cfg),
        SafetyParams::from_config(&cfg),
    )
}

fn limits(axis: usize) -> RampLimits {
    let (p, s) = prob2();
    ramp_limits(&p, &s, axis)
}

/// Assert that one step from `a` to `b` respects the limits.
fn assert_within(a: &AxisRamp, b: &AxisRamp, l: &RampLimits) -> Result<(), TestCaseError> {
    prop_assert!(b.velocity.abs() <= l.velocity + EPS, "{b:?}");
    prop_assert!(b.acceleration.abs() <= l.acceleration + EPS, "{b:?}");
    prop_assert!(
        (b.acceleration - a.acceleration).abs() <= l.jerk * DT * (1.0 + 1e-9) + EPS,
        "jerk: {a:?} -> {b:?}"
    );
    prop_assert!(((b.velocity - a.velocity) / DT - b.acceleration).abs() < 1e-6);
    Ok(())
}

#[test]
fn envelope_solves_its_equation_and_is_zero_at_the_stop() {
    let v = envelope(0.5, 1.2, 0.1);
    assert!((v * 0.1 + v * v / 2.4 - 0.5).abs() < 1e-12, "{v}");
    assert_eq!(envelope(0.0, 1.2, 0.1), 0.0);
    assert_eq!(envelope(-1.0, 1.2, 0.1), 0.0);
    assert_eq!(envelope(1.0, 0.0, 0.1), 0.0);
    assert_eq!(envelope(f64::NAN, 1.0, 0.1), 0.0);
    // Without latency: v^2 / (2 a) = d.
    assert!((envelope(2.0, 1.0, 0.0) - 2.0).abs() < 1e-12);
}

#[test]
fn the_target_is_bounded_by_the_velocity_limit_and_the_envelopes() {
    let l = limits(0);
    assert_eq!(allowed_target(0.0, 10.0, &l), l.velocity);
    assert_eq!(allowed_target(0.0, -10.0, &l), -l.velocity);
    assert_eq!(allowed_target(0.0, f64::NAN, &l), 0.0);
    // At the stop point nothing more towards the limit, anything away from it.
    assert_eq!(allowed_target(l.stop_max, 0.5, &l), 0.0);
    assert_eq!(allowed_target(l.stop_max, -0.5, &l), -0.5);
    assert_eq!(allowed_target(l.stop_min - 0.1, -0.5, &l), 0.0);
    // The P-Rob2: brake 0.4 x 180 deg/s^2, stop 1.25 deg before the limit.
    assert!((l.brake - 72f64.to_radians()).abs() < 1e-12);
    assert!((l.stop_max - 168.75f64.to_radians()).abs() < 1e-12);
}

#[test]
fn a_ramp_from_rest_to_full_speed_is_a_jerk_limited_s_curve() {
    let l = limits(1);
    let mut s = AxisRamp::default();
    let mut n = 0;
    let mut peak_a: f64 = 0.0;
    while s.velocity != l.velocity {
        let next = step(s, l.velocity, &l, DT);
        assert_within(&s, &next, &l).unwrap();
        peak_a = peak_a.max(next.acceleration);
        s = next;
        n += 1;
        assert!(n < 1000, "never reached: {s:?}");
    }
    // 90 deg/s at 180 deg/s^2 and 1800 deg/s^3: 0.5 s + 0.1 s of jerk ramp, within a few cycles.
    let t = n as f64 * DT;
    assert!((0.6..0.65).contains(&t), "{t} s");
    assert!(
        (peak_a - l.acceleration).abs() < 1e-9,
        "full acceleration reached"
    );
    let next = step(s, l.velocity, &l, DT);
    assert_eq!(next.velocity, l.velocity, "stays on the target");
    assert_eq!(next.acceleration, 0.0);
}

#[test]
fn without_a_jerk_limit_the_ramp_is_a_trapezoid() {
    let mut l = limits(1);
    l.jerk = f64::INFINITY;
    let mut s = AxisRamp::default();
    for _ in 0..10 {
        s = step(s, 0.5, &l, DT);
        assert!((s.acceleration - l.acceleration).abs() < 1e-12);
    }
    for _ in 0..200 {
        s = step(s, 0.5, &l, DT);
    }
    assert_eq!(s.velocity, 0.5);
}

proptest! {
    /// Arbitrary targets, changed at arbitrary times, from an arbitrary position: the limits
    /// hold every cycle, the axis never passes its stop points, and the braking-distance check
    /// of the safety layer passes on the commanded state every cycle.
    #[test]
    fn never_exceeds_the_limits_nor_trips_the_braking_check(
        axis in 0usize..6,
        start in -1.0f64..1.0,
        targets in prop::collection::vec((-4.0f64..4.0, 1usize..300), 1..8),
    ) {
        let (_, safety) = prob2();
        let l = limits(axis);
        let mut s = AxisRamp {
            position: l.stop_min + (start + 1.0) / 2.0 * (l.stop_max - l.stop_min),
            ..AxisRamp::default()
        };
        for (target, cycles) in targets {
            for _ in 0..cycles {
                let next = step(s, target, &l, DT);
                assert_within(&s, &next, &l)?;
                prop_assert!(
                    next.position <= l.stop_max + EPS && next.position >= l.stop_min - EPS,
                    "passed a stop point: {next:?} ({}, {})", l.stop_min, l.stop_max
                );
                let mut q = [0.0; 6];
                let mut qd = [0.0; 6];
                q[axis] = next.position;
                qd[axis] = next.velocity;
                prop_assert!(check_braking(&safety, &q, &qd).is_ok(), "{next:?}");
                s = next;
            }
        }
    }

    /// From rest, away from the limits, every target within the velocity limit is reached
    /// and kept, in at most the time of a full S-curve ramp.
    #[test]
    fn reaches_the_target(axis in 0usize..6, share in -1.0f64..=1.0) {
        let l = limits(axis);
        let target = share * l.velocity * 0.5; // stays far from the limits meanwhile
        let mut s = AxisRamp::default();
        let most = ((l.velocity / l.acceleration + l.acceleration / l.jerk) / DT) as usize + 3;
        for _ in 0..most {
            s = step(s, target, &l, DT);
        }
        prop_assert_eq!(s.velocity, target);
        prop_assert!(s.acceleration.abs() < 1e-9);
    }

    /// Full speed straight into a limit: the axis comes to rest before it and stays there.
    #[test]
    fn stops_before_a_joint_limit(axis in 0usize..6, up in any::<bool>(), from in -0.5f64..0.5) {
        let l = limits(axis);
        let target = if up { 10.0 } else { -10.0 };
        let mut s = AxisRamp { position: from, ..AxisRamp::default() };
        for _ in 0..3000 {
            s = step(s, target, &l, DT);
        }
        let stop = if up { l.stop_max } else { l.stop_min };
        prop_assert!(s.velocity.abs() < 1e-9, "{s:?}");
        prop_assert!((s.position - stop).abs() < 0.01, "at rest {s:?}, stop point {stop}");
        prop_assert!(s.position <= l.stop_max + EPS && s.position >= l.stop_min - EPS);
    }
}
