use super::*;
use mcm_shared::sample::STATE_ESTOP;
use nalgebra::{UnitQuaternion, Vector3};

fn prob2() -> Cartesian {
    Cartesian::from_config(&RobotConfig::prob2_default()).unwrap()
}

fn calibrated_at(position: [f64; NUM_AXES], velocity: [f64; NUM_AXES]) -> StateSample {
    StateSample {
        flags: STATE_ALL_CALIBRATED | STATE_ESTOP,
        position,
        velocity,
        ..StateSample::default()
    }
}

fn rotation(s: &TcpState) -> UnitQuaternion<f64> {
    let [x, y, z, w] = s.orientation;
    UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z))
}

#[test]
fn the_p_rob2_at_zero_stands_upright_with_its_flange_up() {
    // Every P-Rob2 axis at 0 deg: the links stacked on axis 1, 0.26 + 0.35 + 0.305 + 0.12 m.
    let mut s = calibrated_at([0.0; 6], [0.0; 6]);
    prob2().compose(&mut s);
    assert_eq!(
        s.flags,
        STATE_ALL_CALIBRATED | STATE_ESTOP | STATE_CARTESIAN
    );
    let p = Vector3::from(s.cartesian.position);
    assert!((p - Vector3::new(0.0, 0.0, 1.035)).norm() < 1e-12, "{p}");
    let z = rotation(&s.cartesian) * Vector3::z();
    assert!((z - Vector3::z()).norm() < 1e-12, "the flange's z axis {z}");
    assert!(s.cartesian.orientation[3] >= 0.0);
    assert_eq!(s.cartesian.linear_velocity, [0.0; 3]);
    assert_eq!(s.cartesian.angular_velocity, [0.0; 3]);
}

#[test]
fn the_tcp_set_is_the_tcp_reported() {
    let mut c = prob2();
    c.follow_tool(&Tcp {
        position: [0.0, 0.0, 0.15],
        orientation: [0.0, 0.0, 0.0, 1.0],
    })
    .unwrap();
    let mut s = calibrated_at([0.0; 6], [0.0; 6]);
    c.compose(&mut s);
    let p = Vector3::from(s.cartesian.position);
    assert!((p - Vector3::new(0.0, 0.0, 1.185)).norm() < 1e-12, "{p}");
    // Axis 1 turning at 90 deg/s turns the TCP on the axis: no linear velocity, 90 deg/s about z.
    let mut s = calibrated_at([0.0; 6], [90.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    c.compose(&mut s);
    let w = Vector3::from(s.cartesian.angular_velocity);
    assert!((w - Vector3::new(0.0, 0.0, 90.0)).norm() < 1e-9, "{w}");
    assert!(Vector3::from(s.cartesian.linear_velocity).norm() < 1e-12);
}

#[test]
fn absent_until_every_axis_is_calibrated() {
    let c = prob2();
    let mut s = calibrated_at([10.0, 20.0, 30.0, 40.0, 50.0, 60.0], [5.0; 6]);
    c.compose(&mut s);
    assert_ne!(s.flags & STATE_CARTESIAN, 0);
    // The same sample, one axis not calibrated: no TCP, and nothing left of the last one.
    s.flags &= !STATE_ALL_CALIBRATED;
    c.compose(&mut s);
    assert_eq!(s.flags, STATE_ESTOP);
    assert_eq!(s.cartesian, TcpState::default());
}

#[test]
fn the_velocity_is_the_rate_of_change_of_the_pose() {
    // Central differences of the pose along the motion (no Jacobian involved): the reported
    // velocities are J·q̇.
    let c = prob2();
    let q = [12.0, -35.0, 60.0, 25.0, -70.0, 140.0];
    let qd = [20.0, -15.0, 30.0, 45.0, -60.0, 90.0];
    let mut s = calibrated_at(q, qd);
    c.compose(&mut s);
    let dt = 1e-6;
    let at = |t: f64| {
        let q: [f64; 6] = core::array::from_fn(|i| q[i] + qd[i] * t);
        let mut s = calibrated_at(q, [0.0; 6]);
        c.compose(&mut s);
        s.cartesian
    };
    let (before, after) = (at(-dt), at(dt));
    let v = (Vector3::from(after.position) - Vector3::from(before.position)) / (2.0 * dt);
    let got = Vector3::from(s.cartesian.linear_velocity);
    assert!((got - v).norm() < 1e-6, "linear {got} vs {v}");
    let turn = rotation(&after) * rotation(&before).inverse();
    let w = turn.scaled_axis().map(f64::to_degrees) / (2.0 * dt);
    let got = Vector3::from(s.cartesian.angular_velocity);
    assert!((got - w).norm() < 1e-4, "angular {got} vs {w} deg/s");
    assert!(got.norm() > 10.0, "the wrist turns: {got}");
}

#[test]
fn an_arm_the_kinematics_cannot_solve_is_refused_with_its_key() {
    let mut cfg = RobotConfig::prob2_default();
    cfg.arm.links[4].a = 0.02;
    let e = Cartesian::from_config(&cfg).unwrap_err();
    assert!(matches!(e, CartesianSetupError::Arm(_)), "{e:?}");
    assert!(e.to_string().contains("arm.link[5].a"), "{e}");
}
