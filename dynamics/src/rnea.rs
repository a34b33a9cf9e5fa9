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
mod tests;
