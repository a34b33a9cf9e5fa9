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
mod tests {
    use super::*;
    use mcm_shared::config::RobotConfig;
    use proptest::prelude::*;

    fn model() -> ArmModel {
        ArmModel::from_config(&RobotConfig::prob2_default())
    }

    fn vec6(range: f64) -> impl Strategy<Value = [f64; N]> {
        proptest::array::uniform6(-range..range)
    }

    /// Mass matrix from unit-acceleration RNEA passes (no velocity, no gravity) + armature.
    fn mass_matrix_by_rnea(m: &ArmModel, q: &[f64; N]) -> Matrix6<f64> {
        let k = m.kinematics(q);
        let mut out = Matrix6::zeros();
        for j in 0..N {
            let mut e = Vector6::zeros();
            e[j] = 1.0;
            out.set_column(
                j,
                &rnea_pass(m, &k, &Vector6::zeros(), &e, Vector3::zeros()),
            );
            out[(j, j)] += m.armature()[j];
        }
        out
    }

    #[test]
    fn armature_is_on_the_diagonal() {
        let mut cfg = RobotConfig::prob2_default();
        let q = [0.3, 0.2, -0.5, 0.1, 0.7, 0.2];
        let with = ArmModel::from_config(&cfg).mass_matrix(&q);
        for a in &mut cfg.axes {
            a.armature_kg_m2 = 0.0;
        }
        let without = ArmModel::from_config(&cfg).mass_matrix(&q);
        let diff = with - without;
        let expect = Matrix6::from_diagonal(&Vector6::new(0.15, 0.15, 0.15, 0.03, 0.03, 0.03));
        assert!((diff - expect).norm() < 1e-12, "{diff}");
    }

    #[test]
    fn solver_falls_back_without_panicking() {
        let bad = Matrix6::from_element(f64::NAN);
        let x = solve_spd(&bad, &Vector6::repeat(1.0));
        assert_eq!(x, Vector6::zeros());
        let diag = -Matrix6::identity();
        assert_eq!(inverse_spd(&diag), Matrix6::zeros());
    }

    proptest! {
        #[test]
        fn crba_equals_unit_acceleration_rnea(q in vec6(3.2)) {
            let m = model();
            let diff = (m.mass_matrix(&q) - mass_matrix_by_rnea(&m, &q)).abs().max();
            prop_assert!(diff < 1e-12, "largest difference {}", diff);
        }

        #[test]
        fn mass_matrix_is_symmetric_positive_definite(q in vec6(3.2)) {
            let m = model().mass_matrix(&q);
            // CRBA is symmetric by construction; the RNEA columns must agree.
            let r = mass_matrix_by_rnea(&model(), &q);
            let asym = (r - r.transpose()).abs().max();
            prop_assert!(asym < 1e-12, "asymmetry {}", asym);
            let eig = m.symmetric_eigenvalues();
            // M = M_links (positive semi-definite) + diag(armature): by Weyl's inequality the
            // smallest eigenvalue is at least the smallest armature (0.03 kg m²).
            prop_assert!(eig.min() >= 0.03 - 1e-12, "eigenvalues {}", eig);
        }

        #[test]
        fn kinetic_energy_is_half_qd_m_qd(q in vec6(3.2), qd in vec6(3.0)) {
            let m = model();
            let v = Vector6::from(qd);
            let from_m = 0.5 * v.dot(&(m.mass_matrix(&q) * v));
            let direct = m.kinetic_energy(&q, &qd);
            let tol = 1e-9 * (1.0 + direct);
            prop_assert!((from_m - direct).abs() < tol, "{} vs {}", from_m, direct);
        }

        #[test]
        fn forward_and_inverse_dynamics_are_inverses(
            q in vec6(3.2),
            qd in vec6(3.0),
            qdd in vec6(10.0),
        ) {
            let m = model();
            let tau = m.inverse_dynamics(&q, &qd, &qdd);
            let back = m.forward_dynamics(&q, &qd, &tau);
            for i in 0..N {
                let err = (back[i] - qdd[i]).abs();
                prop_assert!(err < 1e-8, "axis {}: {} vs {}", i, back[i], qdd[i]);
            }
        }

        /// d/dt (kinetic + potential) = q̇ · τ along the motion: checks the Coriolis and
        /// centrifugal terms against the energy, independently of the RNEA.
        #[test]
        fn power_balance_holds(q in vec6(3.2), qd in vec6(2.0), tau in vec6(20.0)) {
            let m = model();
            let qdd = m.forward_dynamics(&q, &qd, &tau);
            let h = 1e-6;
            let energy = |s: f64| {
                let qs: [f64; N] =
                    core::array::from_fn(|i| q[i] + s * qd[i] + 0.5 * s * s * qdd[i]);
                let vs: [f64; N] = core::array::from_fn(|i| qd[i] + s * qdd[i]);
                m.kinetic_energy(&qs, &vs) + m.potential_energy(&qs)
            };
            let de = (energy(h) - energy(-h)) / (2.0 * h);
            let power: f64 = (0..N).map(|i| qd[i] * tau[i]).sum();
            let tol = 1e-4 * (1.0 + power.abs());
            prop_assert!((de - power).abs() < tol, "dE/dt {} vs power {}", de, power);
        }
    }
}
