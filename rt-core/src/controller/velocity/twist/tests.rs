//! Unit tests of the joint velocities of a TCP velocity: exact away from singularities, the
//! tool frame turned by the TCP's orientation, bounded and slowing towards a singularity, the
//! whole vector scaled into the axes' limits along the same direction.

use super::super::ramp_limits;
use super::*;
use crate::params::JointParams;
use crate::safety::SafetyParams;
use mcm_kinematics::tcp_transform;
use mcm_shared::config::RobotConfig;
use mcm_shared::tool::Tcp;
use mcm_shared::units::deg_to_rad;

fn prob2() -> (Kinematics, [RampLimits; NUM_AXES]) {
    let cfg = RobotConfig::prob2_default();
    let (p, s) = (
        JointParams::from_config(&cfg),
        SafetyParams::from_config(&cfg),
    );
    (
        Kinematics::from_config(&cfg).unwrap(),
        core::array::from_fn(|i| ramp_limits(&p, &s, i)),
    )
}

/// A configuration away from every singularity [rad].
const AWAY: [f64; NUM_AXES] = [0.3, 0.5, 1.0, 0.4, 0.8, -0.3];

fn base(linear: [f64; 3], angular: [f64; 3]) -> Twist {
    Twist {
        linear,
        angular,
        frame: CartesianFrame::Base,
    }
}

#[test]
fn away_from_singularities_the_joint_velocities_give_the_twist_exactly() {
    let (kin, limits) = prob2();
    assert!(margin_ratio(&kin.singularities(&AWAY), &SingularityMargins::DEFAULT) > 1.0);
    let t = base([0.05, -0.02, 0.01], [0.0, 0.1, -0.2]);
    let qd = joint_target(&kin, &AWAY, &t, &limits);
    let twist = kin.tcp_jacobian(&AWAY) * Vector6::from(qd);
    let want = Vector6::new(0.05, -0.02, 0.01, 0.0, 0.1, -0.2);
    assert!((twist - want).norm() < 1e-12, "{twist} vs {want}");
    // Nothing asked, nothing moves.
    let zero = joint_target(&kin, &AWAY, &base([0.0; 3], [0.0; 3]), &limits);
    assert_eq!(zero, [0.0; NUM_AXES]);
}

#[test]
fn the_tool_frame_is_turned_by_the_tcp_orientation_of_the_configuration() {
    let (mut kin, limits) = prob2();
    // A tool turned 90 deg about the flange's x axis, 10 cm out.
    let h = core::f64::consts::FRAC_1_SQRT_2;
    kin.set_tcp(tcp_transform(&Tcp {
        position: [0.0, 0.0, 0.1],
        orientation: [h, 0.0, 0.0, h],
    }))
    .unwrap();
    let t = Twist {
        linear: [0.0, 0.0, 0.03],
        angular: [0.1, 0.0, 0.0],
        frame: CartesianFrame::Tool,
    };
    let qd = joint_target(&kin, &AWAY, &t, &limits);
    let twist = kin.tcp_jacobian(&AWAY) * Vector6::from(qd);
    let r = kin.tcp_pose(&AWAY).rotation;
    let (z, x) = (r * Vector3::z(), r * Vector3::x());
    let want = Vector6::new(
        0.03 * z.x,
        0.03 * z.y,
        0.03 * z.z,
        0.1 * x.x,
        0.1 * x.y,
        0.1 * x.z,
    );
    assert!((twist - want).norm() < 1e-12, "{twist} vs {want}");
    // Not the base frame's axes.
    assert!((twist.fixed_rows::<3>(0) - Vector3::new(0.0, 0.0, 0.03)).norm() > 0.01);
}

#[test]
fn too_fast_for_an_axis_the_whole_vector_slows_along_the_same_direction() {
    let (kin, limits) = prob2();
    let t = base([1.0, 0.0, 0.0], [0.0; 3]);
    let exact = joint_velocities(&kin, &AWAY, &base_twist(&kin, &AWAY, &t));
    let qd = Vector6::from(joint_target(&kin, &AWAY, &t, &limits));
    let share = qd.norm() / exact.norm();
    assert!(share < 1.0, "1 m/s is more than the axes allow here");
    // At most every axis's velocity, and one axis at its limit.
    let worst = (0..NUM_AXES)
        .map(|i| qd[i].abs() / limits[i].velocity)
        .fold(0.0, f64::max);
    assert!((worst - 1.0).abs() < 1e-12, "{worst}");
    // The same direction: every component scaled by the same share.
    assert!((qd - exact * share).norm() < 1e-12);
    let twist = kin.tcp_jacobian(&AWAY) * qd;
    assert!(twist[1].abs() < 1e-12 && twist[2].abs() < 1e-12, "{twist}");
    assert!(twist.fixed_rows::<3>(3).norm() < 1e-12);
}

#[test]
fn an_axis_at_its_stop_point_stops_the_whole_motion_but_not_the_way_back() {
    let (kin, limits) = prob2();
    // Axis 1 at the point where it comes to rest before its upper limit.
    let mut q = AWAY;
    q[0] = limits[0].stop_max;
    let qd0 = joint_velocities(
        &kin,
        &q,
        &base_twist(&kin, &q, &base([0.0, 0.05, 0.0], [0.0; 3])),
    );
    // Which way along y turns axis 1 towards its limit.
    let towards = if qd0[0] > 0.0 { 0.05 } else { -0.05 };
    let stopped = joint_target(&kin, &q, &base([0.0, towards, 0.0], [0.0; 3]), &limits);
    assert_eq!(
        stopped, [0.0; NUM_AXES],
        "towards the limit: every axis at rest"
    );
    let back = joint_target(&kin, &q, &base([0.0, -towards, 0.0], [0.0; 3]), &limits);
    assert!(back[0].abs() > 0.01, "away from it: free {back:?}");
}

/// `AWAY` with the elbow `elbow_rad` from stretched (the measure of the elbow singularity).
fn elbow_at(kin: &Kinematics, elbow_rad: f64) -> [f64; NUM_AXES] {
    // Find q3 by bisection on the measure from AWAY's q3 towards the stretched arm.
    let (mut lo, mut hi) = (-1.0, AWAY[2]);
    let measure = |q3: f64| {
        let mut q = AWAY;
        q[2] = q3;
        kin.singularities(&q).elbow_rad
    };
    // The stretched arm lies between lo and hi on the P-Rob2 (measure 0 there).
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if measure(mid) > elbow_rad {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let mut q = AWAY;
    q[2] = hi;
    q
}

#[test]
fn towards_the_elbow_singularity_the_motion_slows_to_rest_before_it_and_may_leave() {
    let (kin, limits) = prob2();
    // The direction of the TCP's motion the stretched elbow loses (the left singular vector
    // of the Jacobian's smallest singular value), towards the singularity.
    let lost = |q: &[f64; NUM_AXES]| {
        let svd = kin.tcp_jacobian(q).svd(true, false);
        let u = svd.u.unwrap();
        let (i, _) = svd.singular_values.argmin();
        let u = u.column(i).into_owned() * 0.1;
        let qd = joint_velocities(&kin, q, &u);
        let ahead: [f64; NUM_AXES] = core::array::from_fn(|k| q[k] + qd[k] * 1e-4);
        let nearer = kin.singularities(&ahead).elbow_rad < kin.singularities(q).elbow_rad;
        if nearer { u } else { -u }
    };
    let twist = |u: &Vector6<f64>| base([u[0], u[1], u[2]], [u[3], u[4], u[5]]);
    // The share of the requested motion along the lost direction.
    let along = |q: &[f64; NUM_AXES], u: &Vector6<f64>| {
        let qd = Vector6::from(joint_target(&kin, q, &twist(u), &limits));
        for i in 0..NUM_AXES {
            assert!(qd[i].abs() <= limits[i].velocity * (1.0 + 1e-12), "{qd}");
        }
        (kin.tcp_jacobian(q) * qd).dot(u) / u.norm_squared()
    };
    let mut last = f64::INFINITY;
    for deg in [20.0, 10.0, 6.0, 4.0, 3.0, 2.6] {
        let q = elbow_at(&kin, deg_to_rad(deg));
        assert!((kin.singularities(&q).elbow_rad - deg_to_rad(deg)).abs() < 1e-6);
        let share = along(&q, &lost(&q));
        assert!(
            share > 0.0 && share < last,
            "{deg} deg: {share} after {last}"
        );
        last = share;
    }
    assert!(last < 0.1, "at 2.6 deg: {last} of the request");
    // At the stop point (half the 5 deg margin) and nearer: at rest towards it, free away.
    for deg in [2.5, 1.0, 0.1, 0.0] {
        let q = elbow_at(&kin, deg_to_rad(deg));
        let u = lost(&q);
        assert!(along(&q, &u).abs() < 1e-9, "{deg} deg: towards it");
        let qd = joint_target(&kin, &q, &twist(&-u), &limits);
        assert!(qd.iter().all(|x| x.is_finite()));
        if deg > 0.0 {
            assert!(along(&q, &-u) > 0.0, "{deg} deg: away from it");
        }
    }
}

#[test]
fn within_a_margin_the_damping_grows_to_its_largest_at_the_singularity() {
    assert_eq!(damping_squared(1.0), 0.0);
    assert_eq!(damping_squared(3.0), 0.0);
    assert_eq!(damping_squared(0.0), DAMPING_MAX * DAMPING_MAX);
    assert!(damping_squared(0.5) > 0.0 && damping_squared(0.5) < damping_squared(0.2));
    let m = SingularityMargins::DEFAULT;
    let at = |wrist, elbow, shoulder| {
        margin_ratio(
            &Singularities {
                wrist_rad: wrist,
                elbow_rad: elbow,
                shoulder_m: shoulder,
            },
            &m,
        )
    };
    assert!((at(1.0, 1.0, 1.0) - 1.0 / m.wrist_rad).abs() < 1e-12);
    assert!((at(m.wrist_rad / 2.0, 1.0, 1.0) - 0.5).abs() < 1e-12);
    assert!((at(1.0, 1.0, m.shoulder_m / 4.0) - 0.25).abs() < 1e-12);
    assert_eq!(at(f64::NAN, 1.0, 1.0), 0.0);
}
