use super::*;
use mcm_shared::config::RobotConfig;
use proptest::prelude::*;

fn model() -> ArmModel {
    ArmModel::from_config(&RobotConfig::prob2_default())
}

fn gravity_deg(q: [f64; N]) -> [f64; N] {
    model().gravity_torques(&q.map(f64::to_radians))
}

#[test]
fn upright_pose_needs_no_torque() {
    for t in gravity_deg([0.0; N]) {
        assert!(t.abs() < 1e-12, "{t}");
    }
}

#[test]
fn horizontal_arm_with_full_tool_matches_reference() {
    let t = gravity_deg([0.0, 90.0, 0.0, 0.0, 0.0, 0.0]);
    assert!((t[1].abs() - 65.9).abs() < 0.1, "tau2 = {}", t[1]);
    assert!((t[2].abs() - 27.4).abs() < 0.1, "tau3 = {}", t[2]);
    assert!((t[4].abs() - 7.9).abs() < 0.1, "tau5 = {}", t[4]);
    for i in [0, 3, 5] {
        assert!(t[i].abs() < 1e-9, "tau{} = {}", i + 1, t[i]);
    }
    // Sign: the arm falls towards +q2 (flange moves to -x), so holding needs negative torque.
    assert!(t[1] < 0.0 && t[2] < 0.0 && t[4] < 0.0, "{t:?}");
}

#[test]
fn forearm_vertical_matches_reference() {
    let t = gravity_deg([0.0, 90.0, -90.0, 0.0, 0.0, 0.0]);
    assert!((t[1].abs() - 38.5).abs() < 0.1, "tau2 = {}", t[1]);
}

#[test]
fn pure_gravity_matches_hand_calculation() {
    // Upper arm horizontal: tau2 = g * (sum of m_i * horizontal lever arm of body i).
    let m = model();
    let q = [0.0, 90f64.to_radians(), 0.0, 0.0, 0.0, 0.0];
    let masses = m.body_masses();
    let coms = m.com_positions(&q);
    let expected: f64 = (1..N).map(|i| masses[i] * 9.81 * coms[i].x).sum();
    let t = m.gravity_torques(&q);
    assert!((t[1] - expected).abs() < 1e-9, "{} vs {expected}", t[1]);
}

/// Σ Jᵢᵀ (−mᵢ g): the Jacobian-transpose sum of the link weights, from the FK only.
fn jacobian_transpose_gravity(m: &ArmModel, q: &[f64; N]) -> [f64; N] {
    let frames = m.link_frames(q);
    let coms = m.com_positions(q);
    let masses = m.body_masses();
    let g = m.gravity();
    let mut tau = [0.0; N];
    for (j, t) in tau.iter_mut().enumerate() {
        let (z, p) = if j == 0 {
            (Vector3::z(), Vector3::zeros())
        } else {
            (
                frames[j - 1].rotation * Vector3::z(),
                frames[j - 1].translation.vector,
            )
        };
        for i in j..N {
            let jv = z.cross(&(coms[i] - p));
            *t -= jv.dot(&(g * masses[i]));
        }
    }
    tau
}

fn joint_vector() -> impl Strategy<Value = [f64; N]> {
    proptest::array::uniform6(-3.2f64..3.2)
}

proptest! {
    #[test]
    fn rnea_gravity_equals_jacobian_transpose(q in joint_vector()) {
        let m = model();
        let a = m.gravity_torques(&q);
        let b = jacobian_transpose_gravity(&m, &q);
        for i in 0..N {
            prop_assert!((a[i] - b[i]).abs() < 1e-9, "axis {}: {} vs {}", i, a[i], b[i]);
        }
    }

    #[test]
    fn gravity_is_gradient_of_potential_energy(q in joint_vector()) {
        let m = model();
        let g = m.gravity_torques(&q);
        let h = 1e-6;
        for i in 0..N {
            let (mut qp, mut qm) = (q, q);
            qp[i] += h;
            qm[i] -= h;
            let d = (m.potential_energy(&qp) - m.potential_energy(&qm)) / (2.0 * h);
            prop_assert!((g[i] - d).abs() < 1e-5, "axis {}: {} vs dV/dq {}", i, g[i], d);
        }
    }
}
