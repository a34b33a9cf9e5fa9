//! Helpers for the crate's tests, and the tests of the constructor and the TCP.

use super::*;
use mcm_shared::config::RobotConfig;
use nalgebra::{Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;

pub(crate) fn prob2() -> Kinematics {
    Kinematics::from_config(&RobotConfig::prob2_default()).unwrap()
}

/// A TCP transform: 0.1..0.25 m out, a little sideways, turned.
pub(crate) fn tcp_strategy() -> impl Strategy<Value = Isometry3<f64>> {
    (
        prop::array::uniform3(-0.05..0.05f64),
        0.0..0.25f64,
        prop::array::uniform3(-1.0..1.0f64),
    )
        .prop_map(|(xy, z, rpy)| {
            Isometry3::from_parts(
                Translation3::new(xy[0], xy[1], z),
                UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
            )
        })
}

/// Joint values inside the reachable ranges of `kin`.
pub(crate) fn inside(kin: &Kinematics, unit: [f64; N]) -> [f64; N] {
    core::array::from_fn(|i| {
        let r = kin.ranges()[i];
        r.min + (r.max - r.min) * unit[i]
    })
}

pub(crate) fn unit6() -> impl Strategy<Value = [f64; N]> {
    prop::array::uniform6(0.0..1.0f64)
}

/// Position error [m] and rotation error [rad] between two poses.
pub(crate) fn pose_error(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    (
        (a.translation.vector - b.translation.vector).norm(),
        a.rotation.angle_to(&b.rotation),
    )
}

#[test]
fn prob2_is_supported_with_its_reachable_ranges() {
    let k = prob2();
    let r = k.ranges()[1];
    assert!((r.min.to_degrees() + 119.0).abs() < 1e-9, "{r:?}");
    assert!((r.max.to_degrees() - 119.0).abs() < 1e-9, "{r:?}");
    assert!((k.max_velocities()[0].to_degrees() - 90.0).abs() < 1e-9);
    assert_eq!(k.tcp(), Isometry3::identity());
}

/// Each shape the solver cannot handle is refused naming the link's key, its value and what
/// is needed.
#[test]
fn unsupported_arms_are_refused_naming_the_link() {
    type Edit = fn(&mut RobotConfig);
    let cases: [(Edit, &str, &str); 9] = [
        (
            |c| c.arm.links[0].alpha_deg = 45.0,
            "arm.link[1].alpha_deg",
            "45",
        ),
        (
            |c| c.arm.links[1].alpha_deg = 90.0,
            "arm.link[2].alpha_deg",
            "90",
        ),
        (|c| c.arm.links[1].a = 0.0, "arm.link[2].a", "0"),
        (|c| c.arm.links[3].a = 0.02, "arm.link[4].a", "0.02"),
        (
            |c| c.arm.links[3].alpha_deg = 0.0,
            "arm.link[4].alpha_deg",
            "0",
        ),
        (|c| c.arm.links[4].a = 0.01, "arm.link[5].a", "0.01"),
        (|c| c.arm.links[4].d = 0.03, "arm.link[5].d", "0.03"),
        (
            |c| c.arm.links[4].alpha_deg = -30.0,
            "arm.link[5].alpha_deg",
            "-30",
        ),
        (
            |c| {
                c.arm.links[2].a = 0.0;
                c.arm.links[3].d = 0.0;
            },
            "arm.link[4].d",
            "0",
        ),
    ];
    for (edit, key, value) in cases {
        let mut cfg = RobotConfig::prob2_default();
        edit(&mut cfg);
        let err = Kinematics::from_config(&cfg).unwrap_err();
        let msg = err.to_string();
        assert!(
            matches!(&err, KinematicsError::Unsupported { key: k, .. } if k == key),
            "{key}: {err:?}"
        );
        assert!(
            msg.contains(&format!("`{key}` = {value}")) && msg.contains("it needs"),
            "{msg}"
        );
    }
    // Other twists of the same kind are fine: ±90 either way, 270 = -90.
    let mut cfg = RobotConfig::prob2_default();
    cfg.arm.links[0].alpha_deg = -90.0;
    cfg.arm.links[3].alpha_deg = 270.0;
    cfg.arm.links[5].alpha_deg = 33.0;
    Kinematics::from_config(&cfg).unwrap();
}

#[test]
fn invalid_values_are_refused_with_the_key() {
    let mut cfg = RobotConfig::prob2_default();
    cfg.arm.links[2].d = f64::NAN;
    let msg = Kinematics::from_config(&cfg).unwrap_err().to_string();
    assert!(
        msg.contains("arm.link[3].d") && msg.contains("NaN"),
        "{msg}"
    );
    let mut cfg = RobotConfig::prob2_default();
    cfg.arm.links.pop();
    assert_eq!(
        Kinematics::from_config(&cfg).unwrap_err(),
        KinematicsError::WrongCount {
            key: "arm.link",
            found: 5
        }
    );
    let mut cfg = RobotConfig::prob2_default();
    cfg.axes[4].max_velocity_deg_s = 0.0;
    let msg = Kinematics::from_config(&cfg).unwrap_err().to_string();
    assert!(
        msg.contains("axis[5].max_velocity_deg_s") && msg.contains("> 0"),
        "{msg}"
    );
}

#[test]
fn a_tcp_that_is_not_finite_or_not_a_rotation_is_refused() {
    let mut k = prob2();
    let bad = Isometry3::from_parts(
        Translation3::new(0.0, f64::INFINITY, 0.0),
        UnitQuaternion::identity(),
    );
    assert_eq!(
        k.set_tcp(bad),
        Err(TcpError::NotFinite {
            what: "position",
            value: f64::INFINITY
        })
    );
    let skewed = Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(2.0, 0.0, 0.0, 0.0)),
    );
    assert!(matches!(k.set_tcp(skewed), Err(TcpError::NotUnit { norm }) if norm == 2.0));
    assert_eq!(k.tcp(), Isometry3::identity(), "unchanged after a refusal");
    let good = Isometry3::translation(0.0, 0.0, 0.15);
    k.set_tcp(good).unwrap();
    let q = [0.0; N];
    let p = k.tcp_pose(&q).translation.vector;
    assert!((p - Vector3::new(0.0, 0.0, 1.185)).norm() < 1e-12, "{p:?}");
}
