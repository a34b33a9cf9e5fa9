use super::*;
use mcm_shared::config::RobotConfig;

#[test]
fn friction_opposes_motion_and_is_smooth_at_zero() {
    let f = JointFriction {
        coulomb: 3.0,
        viscous: 2.0,
    };
    assert_eq!(f.torque(0.0), 0.0);
    assert!((f.torque(1.0) + 5.0).abs() < 1e-9, "{}", f.torque(1.0));
    assert!((f.torque(-1.0) - 5.0).abs() < 1e-9);
    // Continuous: a tiny velocity gives a tiny torque.
    assert!(f.torque(1e-6).abs() < 1e-3);
    assert_eq!(f.torque(f64::NAN), 0.0);
}

#[test]
fn model_uses_configured_levels() {
    let m = ArmModel::from_config(&RobotConfig::prob2_default());
    let qd = [1.0; NUM_AXES];
    let f = m.friction_torques(&qd);
    let expect = [5.0, 7.0, 5.0, 2.0, 1.8, 1.5];
    for i in 0..NUM_AXES {
        assert!((f[i] + expect[i]).abs() < 1e-9, "axis {i}: {}", f[i]);
        assert_eq!(m.friction_compensation(&qd)[i], -f[i]);
    }
}
