//! Recursive Newton-Euler inverse dynamics (RNEA), in world coordinates.
//!
//! Runs inside the cycle: allocation-free and panic-free (fixed-size nalgebra types).
//!
//! Forward pass: angular velocity/acceleration and the acceleration of every link's origin and
//! centre of mass, starting from a base acceleration of −g (gravity enters as an upward
//! acceleration of the base, Featherstone's trick). Backward pass: the wrench each link
//! transmits to its parent, about the joint's origin; τᵢ = zᵢ₋₁ · nᵢ. Armature torques
//! (`armature · q̈`) are added by the public wrappers.
//!
//! ```
//! use mcm_dynamics::ArmModel;
//! let model = ArmModel::from_config(&mcm_shared::config::RobotConfig::prob2_default());
//! let q = [0.0, 1.0, 0.0, 0.0, 0.0, 0.0];
//! let tau = model.inverse_dynamics(&q, &[0.0; 6], &[0.0; 6]);
//! assert_eq!(tau, model.gravity_torques(&q));
//! ```

use super::model::{ArmModel, Kinematics};
use mcm_shared::NUM_AXES;
use nalgebra::{Vector3, Vector6};

const N: usize = NUM_AXES;

/// One RNEA pass without armature: the joint torques of the six rigid bodies for velocities
/// `qd`, accelerations `qdd` and base-origin acceleration `base_acc` (−g for gravity, zero
/// without).
pub(super) fn rnea_pass(
    model: &ArmModel,
    k: &Kinematics,
    qd: &Vector6<f64>,
    qdd: &Vector6<f64>,
    base_acc: Vector3<f64>,
) -> Vector6<f64> {
    let mut f = [Vector3::zeros(); N];
    let mut n = [Vector3::zeros(); N];
    let mut w = Vector3::zeros();
    let mut wd = Vector3::zeros();
    let mut a = base_acc; // acceleration of the origin of the previous frame
    for i in 0..N {
        let z = k.axis[i];
        let w_new = w + z * qd[i];
        wd += z * qdd[i] + w.cross(&(z * qd[i]));
        w = w_new;
        // The previous origin lies on joint i's axis: it has the same acceleration in both links.
        let r = k.origin[i] - k.joint_origin[i];
        a += wd.cross(&r) + w.cross(&w.cross(&r));
        let rc = k.com[i] - k.origin[i];
        let ac = a + wd.cross(&rc) + w.cross(&w.cross(&rc));
        let b = &model.bodies[i];
        f[i] = ac * b.mass;
        n[i] = k.inertia[i] * wd + w.cross(&(k.inertia[i] * w));
    }
    let mut tau = Vector6::zeros();
    let mut f_child = Vector3::zeros();
    let mut n_child = Vector3::zeros(); // about the origin of frame i (the child's joint)
    for i in (0..N).rev() {
        let p = k.joint_origin[i];
        let n_here =
            n[i] + (k.com[i] - p).cross(&f[i]) + n_child + (k.origin[i] - p).cross(&f_child);
        f_child += f[i];
        n_child = n_here;
        tau[i] = k.axis[i].dot(&n_here);
    }
    tau
}

impl ArmModel {
    /// Joint torques that hold the arm still at `q` against gravity [Nm].
    pub fn gravity_torques(&self, q: &[f64; N]) -> [f64; N] {
        let k = self.kinematics(q);
        rnea_pass(
            self,
            &k,
            &Vector6::zeros(),
            &Vector6::zeros(),
            -self.gravity,
        )
        .into()
    }

    /// Joint torques producing accelerations `qdd` at `q`, `qd`: inertia (incl. armature),
    /// Coriolis/centrifugal and gravity; no friction [Nm].
    pub fn inverse_dynamics(&self, q: &[f64; N], qd: &[f64; N], qdd: &[f64; N]) -> [f64; N] {
        let k = self.kinematics(q);
        let qdd_v = Vector6::from(*qdd);
        let mut tau = rnea_pass(self, &k, &Vector6::from(*qd), &qdd_v, -self.gravity);
        for i in 0..N {
            tau[i] += self.armature[i] * qdd_v[i];
        }
        tau.into()
    }

    /// Coriolis, centrifugal and gravity torques: `inverse_dynamics(q, qd, 0)` [Nm].
    pub fn bias_torques(&self, q: &[f64; N], qd: &[f64; N]) -> [f64; N] {
        let k = self.kinematics(q);
        rnea_pass(
            self,
            &k,
            &Vector6::from(*qd),
            &Vector6::zeros(),
            -self.gravity,
        )
        .into()
    }
}

#[cfg(test)]
mod tests {
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
}
