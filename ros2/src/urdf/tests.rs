//! The generated description read back with an independent parser (urdf-rs), its kinematics
//! and inertials computed from what was parsed and compared with mcm-dynamics' `ArmModel`.

use super::*;
use mcm_dynamics::ArmModel;
use nalgebra::{Isometry3, Rotation3, Unit};
use proptest::prelude::*;
use std::collections::HashMap;
use std::sync::OnceLock;
use urdf_rs::{Joint, JointType, Robot};

const TOL: f64 = 1e-9;

fn prob2() -> RobotConfig {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../deploy/prob2.toml");
    RobotConfig::from_file(&path).expect("deploy/prob2.toml loads")
}

fn opts(prefix: &str) -> UrdfOptions {
    UrdfOptions {
        prefix: prefix.into(),
    }
}

fn parse(cfg: &RobotConfig, prefix: &str) -> Robot {
    let text = generate(cfg, &opts(prefix)).expect("a description");
    urdf_rs::read_from_string(&text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

struct Fixture {
    cfg: RobotConfig,
    model: ArmModel,
    robot: Robot,
}

impl Fixture {
    fn new(cfg: RobotConfig, prefix: &str) -> Fixture {
        Fixture {
            model: ArmModel::from_config(&cfg),
            robot: parse(&cfg, prefix),
            cfg,
        }
    }
}

/// deploy/prob2.toml, no prefix.
fn fixture() -> &'static Fixture {
    static F: OnceLock<Fixture> = OnceLock::new();
    F.get_or_init(|| Fixture::new(prob2(), ""))
}

fn rx(a: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::x_axis(), a).into_inner()
}
fn ry(a: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::y_axis(), a).into_inner()
}
fn rz(a: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::z_axis(), a).into_inner()
}

/// How an origin's rpy becomes a rotation.
type Rpy = fn([f64; 3]) -> Matrix3<f64>;

/// URDF's convention: roll about x, then pitch about y, then yaw about z, all fixed axes:
/// R = Rz(yaw) Ry(pitch) Rx(roll).
fn rpy_urdf(v: [f64; 3]) -> Matrix3<f64> {
    rz(v[2]) * ry(v[1]) * rx(v[0])
}

/// The wrong order, to show the comparison would catch it.
fn rpy_reversed(v: [f64; 3]) -> Matrix3<f64> {
    rx(v[0]) * ry(v[1]) * rz(v[2])
}

/// The joints from the root down to `tip`, following each link's parent joint.
fn chain<'a>(robot: &'a Robot, tip: &str) -> Vec<&'a Joint> {
    let mut out = Vec::new();
    let mut link = tip.to_string();
    while let Some(j) = robot.joints.iter().find(|j| j.child.link == link) {
        out.push(j);
        link = j.parent.link.clone();
        assert!(out.len() <= robot.joints.len(), "a loop above {tip}");
    }
    out.reverse();
    out
}

/// One link of the chain, in the root frame.
struct Body {
    link: String,
    rot: Matrix3<f64>,
    pos: Vector3<f64>,
    mass: f64,
    com: Vector3<f64>,
    kinetic: f64,
}

/// Walk the chain from the root to `tip` with joint angles `q` and velocities `qd` (by joint
/// name, rad and rad/s): each link's pose, centre of mass and kinetic energy, computed from
/// the parsed description only.
fn walk(
    robot: &Robot,
    tip: &str,
    q: &HashMap<String, f64>,
    qd: &HashMap<String, f64>,
    rpy: Rpy,
) -> Vec<Body> {
    let (mut rot, mut pos) = (Matrix3::identity(), Vector3::zeros());
    let (mut w, mut v) = (Vector3::zeros(), Vector3::zeros()); // of the current frame's origin
    let mut out = Vec::new();
    for j in chain(robot, tip) {
        let r_joint = rot * rpy(j.origin.rpy.0);
        let p_joint = pos + rot * Vector3::from(j.origin.xyz.0);
        v += w.cross(&(p_joint - pos));
        match j.joint_type {
            JointType::Revolute => {
                let axis = Unit::new_normalize(Vector3::from(j.axis.xyz.0));
                w += r_joint * axis.into_inner() * qd[&j.name];
                rot = r_joint * Rotation3::from_axis_angle(&axis, q[&j.name]).into_inner();
            }
            JointType::Fixed => rot = r_joint,
            ref t => panic!("joint {} is {t:?}", j.name),
        }
        pos = p_joint;
        let link = robot
            .links
            .iter()
            .find(|l| l.name == j.child.link)
            .expect("the child link exists");
        let inertial = &link.inertial;
        let r_c = rot * rpy(inertial.origin.rpy.0);
        let com = pos + rot * Vector3::from(inertial.origin.xyz.0);
        let i = &inertial.inertia;
        #[rustfmt::skip]
        let inertia = Matrix3::new(
            i.ixx, i.ixy, i.ixz,
            i.ixy, i.iyy, i.iyz,
            i.ixz, i.iyz, i.izz,
        );
        let mass = inertial.mass.value;
        let vc = v + w.cross(&(com - pos));
        let kinetic =
            0.5 * mass * vc.norm_squared() + 0.5 * w.dot(&(r_c * inertia * r_c.transpose() * w));
        out.push(Body {
            link: link.name.clone(),
            rot,
            pos,
            mass,
            com,
            kinetic,
        });
    }
    out
}

fn by_name(cfg: &RobotConfig, prefix: &str, values: &[f64; NUM_AXES]) -> HashMap<String, f64> {
    cfg.axes
        .iter()
        .zip(values)
        .map(|(a, v)| (format!("{prefix}{}", a.name), *v))
        .collect()
}

fn body<'a>(bodies: &'a [Body], link: &str) -> &'a Body {
    bodies
        .iter()
        .find(|b| b.link == link)
        .unwrap_or_else(|| panic!("{link} is on the chain"))
}

/// The largest difference between `body`'s pose and `pose`: (metres, rotation-matrix entries,
/// which for small angles are radians).
fn pose_error(body: &Body, pose: &Isometry3<f64>) -> (f64, f64) {
    let r = pose.rotation.to_rotation_matrix().into_inner();
    (
        (body.pos - pose.translation.vector).amax(),
        (body.rot - r).amax(),
    )
}

/// The description's flange, tool0 and joint frames are the model's at `q`.
fn assert_kinematics(f: &Fixture, prefix: &str, q: &[f64; NUM_AXES]) {
    let zero = [0.0; NUM_AXES];
    let bodies = walk(
        &f.robot,
        &format!("{prefix}tool0"),
        &by_name(&f.cfg, prefix, q),
        &by_name(&f.cfg, prefix, &zero),
        rpy_urdf,
    );
    let flange = f.model.flange_pose(q);
    for tip in ["flange", "tool0"] {
        let (dp, dr) = pose_error(body(&bodies, &format!("{prefix}{tip}")), &flange);
        assert!(dp < TOL && dr < TOL, "{tip} at q = {q:?}: {dp} m, {dr} rad");
    }
    // link_{i+2} turns about joint i+2's axis: DH frame i+1's z, through its origin.
    let frames = f.model.link_frames(q);
    for (i, frame) in frames.iter().take(NUM_AXES - 1).enumerate() {
        let b = body(&bodies, &format!("{prefix}link_{}", i + 2));
        let r = frame.rotation.to_rotation_matrix().into_inner();
        let dp = (b.pos - frame.translation.vector).amax();
        let dz = (b.rot.column(2) - r.column(2)).amax();
        assert!(dp < TOL && dz < TOL, "link_{} at q = {q:?}", i + 2);
    }
}

/// Zeros, every limit, and mixes of them [rad].
fn edge_poses(cfg: &RobotConfig) -> Vec<[f64; NUM_AXES]> {
    let lo: Vec<f64> = cfg.axes.iter().map(|a| a.min_deg.to_radians()).collect();
    let hi: Vec<f64> = cfg.axes.iter().map(|a| a.max_deg.to_radians()).collect();
    let mut out = vec![
        [0.0; NUM_AXES],
        std::array::from_fn(|i| lo[i]),
        std::array::from_fn(|i| hi[i]),
        std::array::from_fn(|i| if i % 2 == 0 { lo[i] } else { hi[i] }),
        std::array::from_fn(|i| if i % 2 == 0 { hi[i] } else { lo[i] }),
    ];
    for i in 0..NUM_AXES {
        for limit in [lo[i], hi[i]] {
            let mut q = [0.0; NUM_AXES];
            q[i] = limit;
            out.push(q);
        }
    }
    out
}

fn q_in_limits() -> impl Strategy<Value = [f64; NUM_AXES]> {
    let axes = &fixture().cfg.axes;
    let range = |i: usize| axes[i].min_deg.to_radians()..=axes[i].max_deg.to_radians();
    (range(0), range(1), range(2), range(3), range(4), range(5))
        .prop_map(|(a, b, c, d, e, f)| [a, b, c, d, e, f])
}

fn qd_in_limits() -> impl Strategy<Value = [f64; NUM_AXES]> {
    let axes = &fixture().cfg.axes;
    let range = |i: usize| {
        let v = axes[i].max_velocity_deg_s.to_radians();
        -v..=v
    };
    (range(0), range(1), range(2), range(3), range(4), range(5))
        .prop_map(|(a, b, c, d, e, f)| [a, b, c, d, e, f])
}

#[test]
fn the_description_is_the_tree_of_the_arm() {
    let f = fixture();
    let r = &f.robot;
    assert_eq!(r.name, "P-Rob2");
    let links: Vec<&str> = r.links.iter().map(|l| l.name.as_str()).collect();
    let mut expected = vec!["base_link".to_string()];
    expected.extend((1..=NUM_AXES).map(|i| format!("link_{i}")));
    expected.extend(["flange".into(), "tool0".into()]);
    assert_eq!(links, expected);
    let joints: Vec<(&str, &str, &str)> = r
        .joints
        .iter()
        .map(|j| {
            (
                j.name.as_str(),
                j.parent.link.as_str(),
                j.child.link.as_str(),
            )
        })
        .collect();
    let mut expected_joints: Vec<(String, String, String)> = f
        .cfg
        .axes
        .iter()
        .enumerate()
        .map(|(i, a)| (a.name.clone(), expected[i].clone(), expected[i + 1].clone()))
        .collect();
    expected_joints.push(("link_6-flange".into(), "link_6".into(), "flange".into()));
    expected_joints.push(("flange-tool0".into(), "flange".into(), "tool0".into()));
    let expected_joints: Vec<(&str, &str, &str)> = expected_joints
        .iter()
        .map(|(a, b, c)| (a.as_str(), b.as_str(), c.as_str()))
        .collect();
    assert_eq!(joints, expected_joints);
    let types: Vec<JointType> = r.joints.iter().map(|j| j.joint_type.clone()).collect();
    let mut expected_types = vec![JointType::Revolute; NUM_AXES];
    expected_types.extend([JointType::Fixed, JointType::Fixed]);
    assert_eq!(types, expected_types);
    // The whole chain hangs from base_link.
    assert_eq!(chain(r, "tool0").len(), NUM_AXES + 2);
    assert_eq!(chain(r, "tool0")[0].parent.link, "base_link");
}

#[test]
fn joints_have_the_configured_limits_and_friction() {
    let f = fixture();
    for (j, a) in f.robot.joints.iter().zip(&f.cfg.axes) {
        assert_eq!(j.name, a.name);
        assert_eq!(j.axis.xyz.0, [0.0, 0.0, 1.0], "{}", j.name);
        // Numbers are printed so that they read back exactly.
        assert_eq!(j.limit.lower, a.min_deg.to_radians(), "{}", j.name);
        assert_eq!(j.limit.upper, a.max_deg.to_radians(), "{}", j.name);
        assert_eq!(
            j.limit.velocity,
            a.max_velocity_deg_s.to_radians(),
            "{}",
            j.name
        );
        assert_eq!(
            j.limit.effort,
            a.max_current_a * a.torque_per_amp(),
            "{}",
            j.name
        );
        let d = j.dynamics.as_ref().expect("dynamics");
        assert_eq!(d.damping, a.viscous_friction_nm_s_rad, "{}", j.name);
        assert_eq!(d.friction, a.coulomb_friction_nm, "{}", j.name);
    }
    // By hand from deploy/prob2.toml: 10 A x 0.12 N m/A x 120 x 0.9, 5 A x 0.05 x 100 x 0.9.
    let j = &f.robot.joints;
    assert!((j[0].limit.effort - 129.6).abs() < 1e-9);
    assert!((j[3].limit.effort - 22.5).abs() < 1e-9);
    assert!((j[0].limit.upper - 170f64.to_radians()).abs() < 1e-15);
    assert!((j[3].limit.velocity - 150f64.to_radians()).abs() < 1e-15);
}

#[test]
fn flange_and_tool0_are_the_models_flange_at_zero_and_at_the_limits() {
    let f = fixture();
    for q in edge_poses(&f.cfg) {
        assert_kinematics(f, "", &q);
    }
    // The upright zero pose, by hand: 0.26 + 0.35 + 0.305 + 0.12 m above the base.
    let bodies = walk(
        &f.robot,
        "tool0",
        &by_name(&f.cfg, "", &[0.0; NUM_AXES]),
        &by_name(&f.cfg, "", &[0.0; NUM_AXES]),
        rpy_urdf,
    );
    let p = body(&bodies, "flange").pos;
    assert!((p - Vector3::new(0.0, 0.0, 1.035)).amax() < 1e-12, "{p}");
}

#[test]
fn the_comparison_catches_a_wrong_rpy_order_or_the_dh_part_on_the_far_side_of_a_joint() {
    let f = fixture();
    let q = [0.3, -0.4, 0.5, 0.6, -0.7, 0.8];
    let qs = by_name(&f.cfg, "", &q);
    let flange = f.model.flange_pose(&q);
    let wrong = walk(&f.robot, "flange", &qs, &qs, rpy_reversed);
    let (dp, dr) = pose_error(body(&wrong, "flange"), &flange);
    assert!(dp.max(dr) > 1e-3, "{dp} {dr}");
    // Each link's fixed DH part on the other side of its joint (frame i = frame i-1 ·
    // Rz(offset) Tz(d) Tx(a) Rx(alpha) · Rz(q), the joint turned last): the same at q = 0,
    // elsewhere not the model's arm.
    let mut turned_last = f.robot.clone();
    for k in 0..turned_last.joints.len() - 1 {
        turned_last.joints[k].origin = f.robot.joints[k + 1].origin.clone();
    }
    let zero = by_name(&f.cfg, "", &[0.0; NUM_AXES]);
    let at_zero = walk(&turned_last, "flange", &zero, &zero, rpy_urdf);
    let (dp, dr) = pose_error(
        body(&at_zero, "flange"),
        &f.model.flange_pose(&[0.0; NUM_AXES]),
    );
    assert!(dp < TOL && dr < TOL, "{dp} {dr}");
    let bodies = walk(&turned_last, "flange", &qs, &qs, rpy_urdf);
    let (dp, dr) = pose_error(body(&bodies, "flange"), &flange);
    assert!(dp.max(dr) > 1e-3, "{dp} {dr}");
}

#[test]
fn inertials_are_the_models_with_the_tool_in_link_6() {
    let f = fixture();
    let masses: Vec<f64> = f
        .robot
        .links
        .iter()
        .map(|l| l.inertial.mass.value)
        .collect();
    let model = f.model.body_masses();
    let mut expected = vec![0.0];
    expected.extend(model);
    expected.extend([0.0, 0.0]);
    for (m, e) in masses.iter().zip(&expected) {
        assert!((m - e).abs() < 1e-12, "{masses:?} vs {expected:?}");
    }
    // By hand: link 6 (0.4 kg) plus the tool (3.8 kg).
    assert!((masses[NUM_AXES] - 4.2).abs() < 1e-12);
    assert!((masses.iter().sum::<f64>() - f.model.total_mass()).abs() < 1e-12);
    for l in &f.robot.links[1..=NUM_AXES] {
        let i = &l.inertial.inertia;
        #[rustfmt::skip]
        let m = Matrix3::new(i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz);
        let e = m.symmetric_eigenvalues();
        assert!(e.iter().all(|v| *v > 0.0), "{}: {e}", l.name);
        let s = e.sum();
        assert!(
            e.iter().all(|v| 2.0 * v <= s + 1e-12),
            "{}: triangle {e}",
            l.name
        );
    }
}

/// The description's centres of mass, masses and kinetic energy are the model's at `q`, `qd`.
fn assert_inertials(f: &Fixture, q: &[f64; NUM_AXES], qd: &[f64; NUM_AXES]) {
    let bodies = walk(
        &f.robot,
        "tool0",
        &by_name(&f.cfg, "", q),
        &by_name(&f.cfg, "", qd),
        rpy_urdf,
    );
    let coms = f.model.com_positions(q);
    for (i, c) in coms.iter().enumerate() {
        let b = body(&bodies, &format!("link_{}", i + 1));
        assert!(
            (b.com - c).amax() < TOL,
            "link_{}: {} vs {}",
            i + 1,
            b.com,
            c
        );
    }
    let rotors: f64 = f
        .model
        .armature()
        .iter()
        .zip(qd)
        .map(|(j, v)| 0.5 * j * v * v)
        .sum();
    let model = f.model.kinetic_energy(q, qd) - rotors;
    let urdf: f64 = bodies.iter().map(|b| b.kinetic).sum();
    assert!(
        (urdf - model).abs() < TOL * model.max(1.0),
        "{urdf} vs {model}"
    );
    let mass: f64 = bodies.iter().map(|b| b.mass).sum();
    assert!((mass - f.model.total_mass()).abs() < 1e-12);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn flange_is_the_models_flange_inside_the_limits(q in q_in_limits()) {
        assert_kinematics(fixture(), "", &q);
    }

    #[test]
    fn centres_of_mass_and_kinetic_energy_are_the_models(
        q in q_in_limits(),
        qd in qd_in_limits(),
    ) {
        assert_inertials(fixture(), &q, &qd);
    }
}

/// An angle [deg]: a multiple of 90° (exact sines and cosines) or any.
fn angle_deg() -> impl Strategy<Value = f64> {
    prop_oneof![
        prop::sample::select(vec![-180.0, -90.0, 0.0, 90.0, 180.0, 270.0]),
        -360.0..360.0f64,
    ]
}

fn any_link() -> impl Strategy<Value = LinkConfig> {
    let length = || -0.5..0.5f64;
    (
        (length(), length(), angle_deg(), angle_deg()),
        0.1..5.0f64,
        prop::array::uniform3(-0.2..0.2f64),
        prop::array::uniform3(0.001..0.05f64),
    )
        .prop_map(
            |((d, a, alpha_deg, offset_deg), mass, com, inertia)| LinkConfig {
                d,
                a,
                alpha_deg,
                offset_deg,
                mass,
                com,
                inertia,
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]

    /// Any DH arm, not only the P-Rob2's right angles.
    #[test]
    fn any_dh_arm_is_the_models_arm(
        links in prop::array::uniform6(any_link()),
        tool_mass in 0.0..5.0f64,
        tool_com in prop::array::uniform3(-0.2..0.2f64),
        tool_moment in 0.0..0.05f64,
        q in prop::array::uniform6(-3.2..3.2f64),
        qd in prop::array::uniform6(-3.0..3.0f64),
    ) {
        let mut cfg = fixture().cfg.clone();
        cfg.arm.links = links.to_vec();
        cfg.arm.tool = mcm_shared::config::ToolConfig {
            mass: tool_mass,
            com: tool_com,
            tcp: None,
            inertia: Some([tool_moment, tool_moment, tool_moment, 0.0, 0.0, 0.0]),
        };
        let f = Fixture::new(cfg, "");
        assert_kinematics(&f, "", &q);
        assert_inertials(&f, &q, &qd);
    }
}

#[test]
fn the_prefix_is_on_every_name_and_the_kinematics_do_not_change() {
    let f = fixture();
    let p = "left_";
    let prefixed = Fixture::new(prob2(), p);
    let r = &prefixed.robot;
    assert_eq!(r.name, "P-Rob2");
    assert_eq!(r.links.len(), f.robot.links.len());
    assert_eq!(r.joints.len(), f.robot.joints.len());
    for (l, plain) in r.links.iter().zip(&f.robot.links) {
        assert_eq!(l.name, format!("{p}{}", plain.name));
        for v in &l.visual {
            let m = v.material.as_ref().expect("a material");
            assert!(m.name.starts_with(p), "{}", m.name);
        }
    }
    for (j, plain) in r.joints.iter().zip(&f.robot.joints) {
        assert_eq!(j.name, format!("{p}{}", plain.name));
        assert_eq!(j.parent.link, format!("{p}{}", plain.parent.link));
        assert_eq!(j.child.link, format!("{p}{}", plain.child.link));
    }
    assert!(!r.materials.is_empty());
    assert!(r.materials.iter().all(|m| m.name.starts_with(p)));
    for q in edge_poses(&f.cfg) {
        assert_kinematics(&prefixed, p, &q);
    }
}

#[test]
fn names_are_escaped() {
    let mut cfg = prob2();
    cfg.robot.name = r#"A&B <"x"> 'y'"#.into();
    cfg.axes[2].name = r#"el"bow<&>"#.into();
    let p = "l&<'";
    let r = parse(&cfg, p);
    assert_eq!(r.name, cfg.robot.name);
    assert_eq!(r.joints[2].name, format!("{p}{}", cfg.axes[2].name));
    assert_eq!(r.links[0].name, format!("{p}base_link"));
}

#[test]
fn numbers_are_finite_and_schematic_shapes_are_real() {
    let f = fixture();
    let text = generate(&f.cfg, &UrdfOptions::default()).unwrap();
    assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
    assert_eq!(text, generate(&prob2(), &UrdfOptions::default()).unwrap());
    for l in &f.robot.links[..=NUM_AXES] {
        assert!(!l.visual.is_empty(), "{} has a shape", l.name);
        assert_eq!(l.visual.len(), l.collision.len(), "{}", l.name);
        for (v, c) in l.visual.iter().zip(&l.collision) {
            assert_eq!(v.origin.xyz, c.origin.xyz);
            match &v.geometry {
                urdf_rs::Geometry::Cylinder { radius, length } => {
                    assert!(radius.is_finite() && *radius > 0.0, "{}", l.name);
                    assert!(length.is_finite() && *length > 0.0, "{}", l.name);
                }
                g => panic!("{}: {g:?}", l.name),
            }
        }
    }
}

#[test]
fn a_configuration_without_distinct_names_or_finite_numbers_is_refused() {
    let base = prob2();
    let p = UrdfOptions::default();

    let mut cfg = base.clone();
    cfg.axes[4].name = cfg.axes[1].name.clone();
    let e = generate(&cfg, &opts("left_")).unwrap_err();
    assert_eq!(
        e,
        UrdfError::DuplicateJointName {
            name: "left_shoulder".into(),
            prefix: "left_".into()
        }
    );
    assert!(e.to_string().contains("`left_shoulder`"), "{e}");

    let mut cfg = base.clone();
    cfg.axes[0].name = "flange-tool0".into();
    assert!(matches!(
        generate(&cfg, &p),
        Err(UrdfError::DuplicateJointName { .. })
    ));

    let mut cfg = base.clone();
    cfg.axes[2].name.clear();
    assert_eq!(
        generate(&cfg, &p),
        Err(UrdfError::EmptyAxisName { axis: 3 })
    );

    let mut cfg = base.clone();
    cfg.axes.pop();
    assert_eq!(
        generate(&cfg, &p),
        Err(UrdfError::WrongCount {
            key: "[[axis]]",
            found: 5
        })
    );
    let mut cfg = base.clone();
    cfg.arm.links.push(cfg.arm.links[0].clone());
    assert_eq!(
        generate(&cfg, &p),
        Err(UrdfError::WrongCount {
            key: "[[arm.link]]",
            found: 7
        })
    );

    let not_finite = |cfg: &RobotConfig| match generate(cfg, &p) {
        Err(UrdfError::NotFinite { what, value }) => {
            assert!(!value.is_finite());
            what
        }
        other => panic!("{other:?}"),
    };
    let mut cfg = base.clone();
    cfg.arm.links[1].d = f64::NAN;
    assert!(not_finite(&cfg).contains("arm.link[2]'s geometry"));
    let mut cfg = base.clone();
    cfg.arm.links[3].inertia[1] = f64::INFINITY;
    assert!(not_finite(&cfg).contains("arm.link[4]'s inertial"));
    let mut cfg = base.clone();
    cfg.arm.tool.com[0] = f64::NAN;
    assert!(not_finite(&cfg).contains("arm.link[6]'s inertial (mass, com, inertia) with arm.tool"));
    let mut cfg = base.clone();
    cfg.axes[4].max_current_a = f64::INFINITY;
    assert!(not_finite(&cfg).contains("axis[5]'s limits"));
    let mut cfg = base;
    cfg.axes[0].coulomb_friction_nm = f64::NAN;
    assert!(not_finite(&cfg).contains("axis[1]'s friction"));
}

fn scratch_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mcm-ros2-urdf-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn write_replaces_the_file_whole() {
    let dir = scratch_dir("write");
    let path = dir.join("robot_description.urdf");
    std::fs::write(&path, "an older, longer description than the new one").unwrap();
    write(&path, "<robot/>").unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "<robot/>");
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["robot_description.urdf"], "no temporary file left");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_write_that_fails_names_the_path() {
    let dir = scratch_dir("write-fails");
    let path = dir.join("missing").join("robot.urdf");
    let e = write(&path, "<robot/>").unwrap_err();
    assert!(
        matches!(&e, UrdfWriteError::Write { path: p, .. } if *p == path),
        "{e:?}"
    );
    assert!(e.to_string().contains(&path.display().to_string()), "{e}");
    // A directory in the way of the rename.
    let taken = dir.join("taken");
    std::fs::create_dir(&taken).unwrap();
    std::fs::write(taken.join("x"), "").unwrap();
    let e = write(&taken, "<robot/>").unwrap_err();
    assert!(
        matches!(&e, UrdfWriteError::Rename { to, .. } if *to == taken),
        "{e:?}"
    );
    assert!(e.to_string().contains(&taken.display().to_string()), "{e}");
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, ["taken"], "the temporary file is removed");
    std::fs::remove_dir_all(&dir).unwrap();
}
