//! Joint-space mass matrix and forward dynamics.
//!
//! Runs inside the cycle: allocation-free and panic-free (fixed-size nalgebra types; the
//! Cholesky factorisation of a `Matrix6` lives on the stack).
//!
//! The mass matrix comes from the composite-rigid-body algorithm (CRBA) in world coordinates
//! plus the armature on the diagonal; the tests check it against unit-acceleration RNEA
//! columns and against the kinetic energy computed from the link velocities. Forward
//! dynamics solves `M(q) q̈ = τ − b(q, q̇)` by Cholesky.
//!
//! ```
//! use mcm_dynamics::ArmModel;
//! let model = ArmModel::from_config(&mcm_shared::config::RobotConfig::prob2_default());
//! let q = [0.1, 0.5, -0.3, 0.0, 0.4, 0.0];
//! let qdd = model.forward_dynamics(&q, &[0.0; 6], &model.gravity_torques(&q));
//! assert!(qdd.iter().all(|a| a.abs() < 1e-9)); // held by its gravity torques
//! ```

use super::model::{ArmModel, Kinematics};
use super::rnea::rnea_pass;
use mcm_shared::NUM_AXES;
use nalgebra::{Cholesky, Matrix3, Matrix6, Vector3, Vector6};

const N: usize = NUM_AXES;

/// Solve `a x = b` for a symmetric positive definite `a` by Cholesky. If the factorisation
/// fails (only for non-finite or non-positive-definite input, which a valid model cannot
/// produce from finite q, q̇), falls back to the diagonal: `xᵢ = bᵢ / aᵢᵢ` where `aᵢᵢ > 0`,
/// else 0. Never panics.
pub fn solve_spd(a: &Matrix6<f64>, b: &Vector6<f64>) -> Vector6<f64> {
    match Cholesky::new(*a) {
        Some(c) => c.solve(b),
        None => diagonal_solve(a, b),
    }
}

fn diagonal_solve(a: &Matrix6<f64>, b: &Vector6<f64>) -> Vector6<f64> {
    let mut x = Vector6::zeros();
    for i in 0..N {
        let d = a[(i, i)];
        if d > 0.0 && d.is_finite() && b[i].is_finite() {
            x[i] = b[i] / d;
        }
    }
    x
}

/// Inverse of a symmetric positive definite matrix (same fallback as [`solve_spd`]).
pub fn inverse_spd(a: &Matrix6<f64>) -> Matrix6<f64> {
    match Cholesky::new(*a) {
        Some(c) => c.inverse(),
        None => {
            let mut inv = Matrix6::zeros();
            for i in 0..N {
                let d = a[(i, i)];
                if d > 0.0 && d.is_finite() {
                    inv[(i, i)] = 1.0 / d;
                }
            }
            inv
        }
    }
}

impl ArmModel {
    /// Joint-space mass matrix M(q), including the armature on the diagonal [kg m²].
    pub fn mass_matrix(&self, q: &[f64; N]) -> Matrix6<f64> {
        let k = self.kinematics(q);
        self.mass_matrix_kin(&k)
    }

    /// Composite-rigid-body algorithm in world coordinates. For joint i, the bodies i..6
    /// turning rigidly about axis zᵢ through pᵢ at unit rate have linear momentum
    /// `L = m·zᵢ × (c − pᵢ)` and angular momentum about pᵢ `H = I_p·zᵢ` (m, c, I_p: mass,
    /// centre of mass, inertia about pᵢ of the composite). Mⱼᵢ (j ≤ i) is the projection of
    /// that momentum, taken about pⱼ, on zⱼ: `zⱼ · (H + (pᵢ − pⱼ) × L)`.
    pub(super) fn mass_matrix_kin(&self, k: &Kinematics) -> Matrix6<f64> {
        let spread = |r: Vector3<f64>| Matrix3::identity() * r.norm_squared() - r * r.transpose();
        let mut m = Matrix6::zeros();
        let mut mass = 0.0;
        let mut moment = Vector3::zeros(); // Σ m c
        let mut inertia_o = Matrix3::zeros(); // about the world origin
        for i in (0..N).rev() {
            let b = &self.bodies[i];
            mass += b.mass;
            moment += k.com[i] * b.mass;
            inertia_o += k.inertia[i] + spread(k.com[i]) * b.mass;
            let c = moment / mass;
            let p = k.joint_origin[i];
            let z = k.axis[i];
            let inertia_p = inertia_o - spread(c) * mass + spread(c - p) * mass;
            let lin = z.cross(&(c - p)) * mass;
            let ang = inertia_p * z;
            for j in 0..=i {
                let v = k.axis[j].dot(&(ang + (p - k.joint_origin[j]).cross(&lin)));
                m[(j, i)] = v;
                m[(i, j)] = v;
            }
            m[(i, i)] += self.armature[i];
        }
        m
    }

    /// Joint accelerations produced by joint torques `tau` at `q`, `qd` (no friction):
    /// q̈ = M⁻¹ (τ − C q̇ − g) [rad/s²]. The inverse of [`ArmModel::inverse_dynamics`].
    pub fn forward_dynamics(&self, q: &[f64; N], qd: &[f64; N], tau: &[f64; N]) -> [f64; N] {
        let (m, bias) = self.mass_matrix_and_bias(q, qd);
        solve_spd(&m, &(Vector6::from(*tau) - bias)).into()
    }

    /// The mass matrix M(q) (armature included, as [`ArmModel::mass_matrix`]) and the bias
    /// torques b(q, q̇) (Coriolis, centrifugal, gravity, as [`ArmModel::bias_torques`]) from one
    /// kinematics pass: what an integrator of `M q̈ = τ − b` needs per step.
    pub fn mass_matrix_and_bias(
        &self,
        q: &[f64; N],
        qd: &[f64; N],
    ) -> (Matrix6<f64>, Vector6<f64>) {
        let k = self.kinematics(q);
        let m = self.mass_matrix_kin(&k);
        let bias = rnea_pass(
            self,
            &k,
            &Vector6::from(*qd),
            &Vector6::zeros(),
            -self.gravity,
        );
        (m, bias)
    }
}

#[cfg(test)]
mod tests;
