use crate::N;
use crate::tests::{inside, pose_error, prob2, tcp_strategy, unit6};
use mcm_dynamics::ArmModel;
use mcm_shared::config::RobotConfig;
use nalgebra::{Isometry3, Vector3, Vector6};
use proptest::prelude::*;

#[test]
fn reference_poses_of_the_prob2() {
    let k = prob2();
    let deg = |v: [f64; N]| v.map(f64::to_radians);
    for (q, p) in [
        ([0.0; N], [0.0, 0.0, 1.035]),
        ([0.0, 90.0, 0.0, 0.0, 0.0, 0.0], [-0.775, 0.0, 0.26]),
        ([0.0, 90.0, -90.0, 0.0, 0.0, 0.0], [-0.35, 0.0, 0.685]),
    ] {
        let got = k.flange_pose(&deg(q)).translation.vector;
        assert!((got - Vector3::from(p)).norm() < 1e-12, "{q:?}: {got:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// With the TCP on the flange, the TCP pose is `mcm_dynamics`' flange pose.
    #[test]
    fn flange_pose_equals_the_dynamics_flange_pose(unit in unit6()) {
        let k = prob2();
        let model = ArmModel::from_config(&RobotConfig::prob2_default());
        let q = inside(&k, unit);
        let (dp, dr) = pose_error(&k.tcp_pose(&q), &model.flange_pose(&q));
        prop_assert!(dp < 1e-12 && dr < 1e-9, "{q:?}: {dp} m, {dr} rad");
        let j = k.tcp_jacobian(&q) - model.flange_jacobian(&q);
        prop_assert!(j.amax() < 1e-12, "{q:?}: Jacobians differ by {}", j.amax());
    }

    /// Each Jacobian column is the derivative of the TCP pose along that joint (central
    /// differences): the TCP origin's velocity and the angular velocity, in base axes.
    #[test]
    fn jacobian_is_the_derivative_of_the_tcp_pose(unit in unit6(), tcp in tcp_strategy()) {
        let mut k = prob2();
        k.set_tcp(tcp).unwrap();
        let q = inside(&k, unit);
        let j = k.tcp_jacobian(&q);
        let h = 1e-6;
        for i in 0..N {
            let (mut plus, mut minus) = (q, q);
            plus[i] += h;
            minus[i] -= h;
            let (a, b): (Isometry3<f64>, Isometry3<f64>) = (k.tcp_pose(&plus), k.tcp_pose(&minus));
            let v = (a.translation.vector - b.translation.vector) / (2.0 * h);
            let w = (a.rotation * b.rotation.inverse()).scaled_axis() / (2.0 * h);
            let fd = Vector6::new(v.x, v.y, v.z, w.x, w.y, w.z);
            let col = j.column(i);
            prop_assert!((col - fd).amax() < 1e-8, "joint {}: {col:?} vs {fd:?}", i + 1);
        }
    }

    /// The TCP is the flange times the TCP transform.
    #[test]
    fn tcp_pose_is_the_flange_times_the_tcp(unit in unit6(), tcp in tcp_strategy()) {
        let mut k = prob2();
        k.set_tcp(tcp).unwrap();
        let q = inside(&k, unit);
        let (dp, dr) = pose_error(&k.tcp_pose(&q), &(k.flange_pose(&q) * tcp));
        prop_assert!(dp < 1e-12 && dr < 1e-12);
    }
}
