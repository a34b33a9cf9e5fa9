use super::*;
use mcm_shared::config::RobotConfig;
use mcm_shared::tool::Tcp;

fn model() -> ArmModel {
    ArmModel::from_config(&RobotConfig::prob2_default())
}

fn deg(v: [f64; N]) -> [f64; N] {
    v.map(f64::to_radians)
}

/// Poses that move the elbow as well as the wrist: the load's lever about the shoulder and
/// the elbow changes apart from its orientation.
fn exciting_poses() -> [[f64; N]; 4] {
    [
        deg([0.0, 0.0, 25.0, 0.0, 35.0, 0.0]),
        deg([0.0, 0.0, 25.0, 90.0, -35.0, 90.0]),
        deg([0.0, 0.0, -25.0, -90.0, 35.0, 0.0]),
        deg([0.0, 0.0, -25.0, 0.0, -35.0, -90.0]),
    ]
}

fn loaded(model: &ArmModel, mass: f64, c: [f64; 3]) -> ArmModel {
    let mut truth = model.clone();
    truth.set_tool(
        &Tool::new(
            Tcp::FLANGE,
            mass,
            c,
            Some([0.01, 0.01, 0.005, 0.0, 0.0, 0.0]),
        )
        .unwrap(),
    );
    truth
}

#[test]
fn exact_torques_give_the_load_exactly() {
    let m = model();
    for (mass, c) in [
        (2.0, [0.0, 0.0, 0.06]),
        (0.7, [0.03, -0.02, 0.11]),
        (4.5, [-0.05, 0.04, 0.0]),
    ] {
        let truth = loaded(&m, mass, c);
        let mut est = PayloadEstimator::new();
        for q in exciting_poses() {
            est.add(&m, &q, &truth.gravity_torques(&q));
        }
        let p = est.estimate().unwrap();
        assert!((p.mass - mass).abs() < 1e-9, "{p:?} for {mass} kg");
        for k in 0..3 {
            assert!((p.center_of_mass[k] - c[k]).abs() < 1e-9, "{p:?} for {c:?}");
        }
        // The residual from the normal system: rounding leaves about 1e-7 N·m of nothing.
        assert!(p.residual_nm < 1e-6, "{p:?}");
    }
}

/// The configured tool does not bias the estimate: its load is taken off the model.
#[test]
fn the_configured_tool_is_not_counted_in() {
    let m = model();
    assert!(
        m.tool().mass > 1.0,
        "the default configuration carries a tool"
    );
    let truth = loaded(&m, 1.2, [0.0, 0.01, 0.05]);
    let mut est = PayloadEstimator::new();
    for q in exciting_poses() {
        est.add(&m, &q, &truth.gravity_torques(&q));
    }
    let p = est.estimate().unwrap();
    assert!((p.mass - 1.2).abs() < 1e-9, "{p:?}");
}

/// Torques with noise (a deterministic sequence of ±0.05 N·m, the size friction leaves after
/// averaging): the estimate stays within the targets, and the residual reports the noise.
#[test]
fn noisy_torques_give_the_load_within_the_targets_and_a_residual() {
    let m = model();
    let truth = loaded(&m, 2.0, [0.0, 0.0, 0.06]);
    let mut est = PayloadEstimator::new();
    let mut seed = 7_u64;
    let mut noise = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.1
    };
    for q in exciting_poses() {
        let tau = truth.gravity_torques(&q).map(|t| t + noise());
        est.add(&m, &q, &tau);
    }
    let p = est.estimate().unwrap();
    assert!((p.mass - 2.0).abs() < 0.1, "{p:?}");
    let c = p.center_of_mass;
    let err = ((c[0]).powi(2) + (c[1]).powi(2) + (c[2] - 0.06).powi(2)).sqrt();
    assert!(err < 0.01, "{p:?}");
    assert!(p.residual_nm > 0.01 && p.residual_nm < 0.05, "{p:?}");
}

/// Moving only the wrist of the upright arm: the wrist's centre stays above the shoulder and
/// the elbow, every axis sees only the first moment about the wrist's centre, and the mass
/// cannot be told from its distance along the flange's axis.
#[test]
fn wrist_moves_of_the_upright_arm_are_refused_as_ill_conditioned() {
    let m = model();
    let truth = loaded(&m, 2.0, [0.0, 0.0, 0.06]);
    let mut est = PayloadEstimator::new();
    let mut judged = PayloadEstimator::new();
    for q in [
        deg([0.0, 0.0, 0.0, 0.0, 35.0, 0.0]),
        deg([0.0, 0.0, 0.0, 90.0, -35.0, 90.0]),
        deg([0.0, 0.0, 0.0, -90.0, 35.0, 0.0]),
        deg([0.0, 0.0, 0.0, 0.0, -35.0, -90.0]),
    ] {
        est.add(&m, &q, &truth.gravity_torques(&q));
        judged.add_pose(&m, &q);
    }
    assert!(judged.condition() > MAX_CONDITION, "{}", judged.condition());
    assert!(matches!(
        est.estimate(),
        Err(PayloadError::IllConditioned {
            limit: MAX_CONDITION,
            ..
        })
    ));
    // One pose is never enough, nor none.
    let mut one = PayloadEstimator::new();
    one.add_pose(&m, &exciting_poses()[0]);
    assert!(one.condition() > MAX_CONDITION);
    assert_eq!(PayloadEstimator::new().condition(), f64::INFINITY);
}

/// The elbow bent by one degree only: the mass is barely told from its distance; refused
/// although exact torques would solve (a little noise would not).
#[test]
fn nearly_degenerate_poses_are_refused_with_their_condition_number() {
    let m = model();
    let truth = loaded(&m, 2.0, [0.0, 0.0, 0.06]);
    let mut est = PayloadEstimator::new();
    for q in exciting_poses() {
        let q = [
            q[0],
            q[1],
            q[2].signum() * 1f64.to_radians(),
            q[3],
            q[4],
            q[5],
        ];
        est.add(&m, &q, &truth.gravity_torques(&q));
    }
    let condition = est.condition();
    assert!(
        condition.is_finite() && condition > MAX_CONDITION,
        "{condition}"
    );
    assert_eq!(
        est.estimate(),
        Err(PayloadError::IllConditioned {
            condition,
            limit: MAX_CONDITION
        })
    );
    assert!(est.judge().is_err());
}

#[test]
fn the_exciting_poses_are_well_conditioned() {
    let m = model();
    let mut judged = PayloadEstimator::new();
    for q in exciting_poses() {
        judged.add_pose(&m, &q);
    }
    assert!(judged.condition() < 10.0, "{}", judged.condition());
}

#[test]
fn non_finite_input_is_refused_without_panic() {
    let m = model();
    let mut est = PayloadEstimator::new();
    for q in exciting_poses() {
        est.add(&m, &q, &[0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0]);
    }
    assert_eq!(est.estimate(), Err(PayloadError::NotFinite));
    assert_eq!(est.condition(), f64::INFINITY);
}

/// No load: mass about 0, no centre of mass reported.
#[test]
fn no_load_reports_no_centre_of_mass() {
    let m = model();
    let bare = loaded(&m, 0.0, [0.0; 3]);
    let mut est = PayloadEstimator::new();
    for q in exciting_poses() {
        est.add(&m, &q, &bare.gravity_torques(&q).map(|t| t - 0.001));
    }
    let p = est.estimate().unwrap();
    assert!(p.mass < 0.01, "{p:?}");
    assert_eq!(p.center_of_mass, [0.0; 3]);
}
