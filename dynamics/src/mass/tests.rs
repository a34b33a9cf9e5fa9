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
