use super::*;

fn model() -> ArmModel {
    ArmModel::from_config(&RobotConfig::prob2_default())
}

fn deg(v: [f64; N]) -> [f64; N] {
    v.map(f64::to_radians)
}

fn assert_pos(q: [f64; N], expect: [f64; 3]) {
    let p = model().flange_pose(&deg(q)).translation.vector;
    let e = Vector3::from(expect);
    assert!(
        (p - e).norm() < 1e-9,
        "q = {q:?}: flange at {p:?}, expected {e:?}"
    );
}

#[test]
fn forward_kinematics_matches_reference_poses() {
    assert_pos([0.0; N], [0.0, 0.0, 1.035]);
    assert_pos([0.0, 90.0, 0.0, 0.0, 0.0, 0.0], [-0.775, 0.0, 0.26]);
    assert_pos([0.0, 90.0, -90.0, 0.0, 0.0, 0.0], [-0.35, 0.0, 0.685]);
}

#[test]
fn link_frames_end_at_flange_and_rotations_are_proper() {
    let m = model();
    let q = [0.3, -0.7, 1.1, 0.4, -0.9, 2.0];
    let frames = m.link_frames(&q);
    let f = m.flange_pose(&q);
    assert!((frames[5].translation.vector - f.translation.vector).norm() < 1e-12);
    assert!(frames[5].rotation.angle_to(&f.rotation) < 1e-9);
    for r in m.kinematics(&q).rot {
        assert!((r * r.transpose() - Matrix3::identity()).norm() < 1e-12);
        assert!((r.determinant() - 1.0).abs() < 1e-12);
    }
}

#[test]
fn tool_is_lumped_into_link_6() {
    let m = model();
    let b = m.bodies[5];
    assert!((b.mass - 4.2).abs() < 1e-12);
    // (0.4 * -0.02 + 3.8 * 0.08) / 4.2
    assert!((b.com.z - 0.296 / 4.2).abs() < 1e-12);
    assert!((m.total_mass() - 16.7).abs() < 1e-9, "{}", m.total_mass());
    let mut light = m.clone();
    light.set_tool(&Tool::NONE);
    assert_eq!(light.bodies[5].mass, 0.4);
    assert!((light.bodies[5].inertia - m.links[5].inertia).norm() < 1e-15);
    assert_eq!(light.tool(), &Tool::NONE);
}

/// A tool's own inertia adds `ωᵀ I ω / 2` to the kinetic energy, `ω` the flange's angular
/// velocity: the mass matrix grows by `Aᵀ R I Rᵀ A` (A: the joint axes, R: the flange's
/// rotation), whatever the tool's mass and centre of mass.
#[test]
fn a_tool_inertia_is_added_to_body_6() {
    let point = model();
    let mut solid = point.clone();
    let t = *point.tool();
    let inertia = [0.02, 0.03, 0.04, 0.005, -0.002, 0.001];
    solid.set_tool(&Tool::new(t.tcp, t.mass, t.center_of_mass, Some(inertia)).unwrap());
    assert_eq!(solid.tool().inertia, inertia);
    let q = [0.3, -0.7, 1.1, 0.4, -0.9, 2.0];
    let k = point.kinematics(&q);
    let [ixx, iyy, izz, ixy, ixz, iyz] = inertia;
    let i = Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
    let r = k.rot[5];
    let a = nalgebra::Matrix3x6::from_columns(&k.axis);
    let expected = a.transpose() * r * i * r.transpose() * a;
    let grown = solid.mass_matrix(&q) - point.mass_matrix(&q);
    assert!((grown - expected).norm() < 1e-12, "{grown} vs {expected}");
    assert!(expected.norm() > 1e-3);
    // Gravity does not see an inertia.
    let g = |m: &ArmModel| Vector6::from(m.gravity_torques(&q));
    assert!((g(&solid) - g(&point)).norm() < 1e-12);
}

#[test]
fn invalid_config_is_refused_with_the_key() {
    let mut cfg = RobotConfig::prob2_default();
    cfg.arm.links[2].mass = -1.0;
    let e = ArmModel::try_from_config(&cfg).unwrap_err();
    assert_eq!(
        e.to_string(),
        "config key `arm.link[3].mass` = -1 is not allowed: a finite mass > 0 kg"
    );
    let mut cfg = RobotConfig::prob2_default();
    cfg.arm.links.pop();
    let e = ArmModel::try_from_config(&cfg).unwrap_err();
    assert_eq!(
        e,
        DynamicsError::WrongCount {
            key: "arm.link",
            found: 5
        }
    );
}

#[test]
fn jacobian_matches_finite_differences_of_fk() {
    let m = model();
    let q = [0.2, 0.5, -0.4, 0.9, 0.6, -1.2];
    let j = m.flange_jacobian(&q);
    let h = 1e-6;
    for i in 0..N {
        let (mut qp, mut qm) = (q, q);
        qp[i] += h;
        qm[i] -= h;
        let dp = (m.flange_pose(&qp).translation.vector - m.flange_pose(&qm).translation.vector)
            / (2.0 * h);
        assert!(
            (dp - j.fixed_view::<3, 1>(0, i)).norm() < 1e-6,
            "column {i}"
        );
    }
}
