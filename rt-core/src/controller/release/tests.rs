//! Unit tests of the soft speed limit (properties over random speeds), and in [`scenario`] its
//! effect on the whole simulated robot.

use super::*;
use proptest::prelude::*;

const LIM: SoftSpeedLimit = SoftSpeedLimit {
    onset: 0.8,
    limit: 1.6,
};

#[test]
fn zero_up_to_the_onset_and_strong_at_the_limit() {
    for v in [0.0, 0.1, -0.5, 0.8, -0.8] {
        assert_eq!(LIM.torque(v, 100.0, 130.0), 0.0, "{v}");
    }
    // at the limit: 1.5 b w = 0.75 b (v_max - v_on)
    let t = LIM.torque(1.6, 100.0, 130.0);
    assert!((t + 60.0).abs() < 1e-9, "{t}");
    assert!((LIM.resisting_at_limit(100.0) - 60.0).abs() < 1e-9);
    assert!((LIM.torque(-1.6, 100.0, 130.0) - 60.0).abs() < 1e-9);
    // capped at the drive's torque
    assert_eq!(LIM.torque(10.0, 100.0, 130.0), -130.0);
    // no damping for a velocity that is not finite, or without a slope
    assert_eq!(LIM.torque(f64::NAN, 100.0, 130.0), 0.0);
    assert_eq!(LIM.torque(f64::INFINITY, 100.0, 130.0), 0.0);
    assert_eq!(LIM.torque(1.5, 0.0, 130.0), 0.0);
}

#[test]
fn the_p_rob2_slopes_come_from_the_inertia_at_the_pose() {
    let cfg = RobotConfig::prob2_default();
    let model = ArmModel::from_config(&cfg);
    let folded = damping_slopes(&model, &[0.0; NUM_AXES], 0.3, 0.005);
    let stretched = damping_slopes(&model, &[0.0, 1.5, -1.5, 0.0, 0.0, 0.0], 0.3, 0.005);
    for i in 0..NUM_AXES {
        // at least the armature's share, finite
        assert!(
            folded[i] >= 0.3 * cfg.axes[i].armature_kg_m2 / 0.005 * 0.999,
            "{folded:?}"
        );
        assert!(folded[i].is_finite() && stretched[i].is_finite());
    }
    assert_ne!(
        folded[0], stretched[0],
        "axis 1's inertia depends on the pose"
    );
}

proptest! {
    #[test]
    fn opposes_the_velocity_and_is_bounded(
        v in -20.0f64..20.0,
        onset in 0.1f64..3.0,
        band in 0.01f64..3.0,
        slope in 0.0f64..1000.0,
        tau_max in 0.1f64..200.0,
    ) {
        let l = SoftSpeedLimit { onset, limit: onset + band };
        let t = l.torque(v, slope, tau_max);
        prop_assert!(t * v <= 0.0, "{t} opposes {v}");
        prop_assert!(t.abs() <= tau_max);
        if v.abs() <= onset {
            prop_assert_eq!(t, 0.0);
        }
    }

    #[test]
    fn continuous_and_monotonic(
        v in -5.0f64..5.0,
        dv in 1e-9f64..1e-4,
        slope in 0.0f64..1000.0,
    ) {
        let tau_max = 130.0;
        let a = LIM.torque(v, slope, tau_max);
        let b = LIM.torque(v + dv, slope, tau_max);
        // the slope never exceeds `slope`: continuous (Lipschitz)
        prop_assert!((b - a).abs() <= slope * dv * (1.0 + 1e-9) + 1e-12, "{a} {b}");
        // more speed, at least as much damping
        if v >= 0.0 {
            prop_assert!(b <= a + 1e-12);
        }
    }
}

#[cfg(feature = "sim")]
mod scenario;
