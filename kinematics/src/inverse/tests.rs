use super::*;
use crate::tests::{inside, pose_error, prob2, tcp_strategy, unit6};
use mcm_shared::config::RobotConfig;
use proptest::prelude::*;

const WIDE: AxisRange = AxisRange {
    min: -4.0 * PI,
    max: 4.0 * PI,
};

/// FK of every solution is the target: 1 µm and 1e-9 rad... tighter: the closed form is exact
/// to rounding.
fn assert_all_reach(k: &Kinematics, target: &Isometry3<f64>, sols: &Solutions) {
    for s in sols {
        let (dp, dr) = pose_error(&k.tcp_pose(&s.q), target);
        assert!(dp < 1e-9 && dr < 1e-9, "{s:?}: {dp} m, {dr} rad off");
        for (i, (v, r)) in s.q.iter().zip(k.ranges()).enumerate() {
            assert!(
                (r.min..=r.max).contains(v),
                "axis {} = {v} outside {r:?}",
                i + 1
            );
        }
    }
}

/// The first solution is `q` within `tol` [rad] on every axis.
fn assert_first_is(sols: &Solutions, q: &[f64; N], tol: f64) {
    let first = sols.first().expect("a solution");
    let d = first
        .q
        .iter()
        .zip(q)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        d < tol,
        "first solution {:?}, seed {q:?}: {d} rad apart",
        first.q
    );
}

fn assert_sorted(k: &Kinematics, sols: &Solutions, seed: &[f64; N]) {
    for w in sols.windows(2) {
        assert!(
            travel_time(seed, &w[0].q, k.max_velocities())
                <= travel_time(seed, &w[1].q, k.max_velocities()),
            "not sorted: {w:?}"
        );
    }
}

/// An arm of the supported kind with random lengths, offsets and twist signs, every axis
/// with two turns of range either way.
/// With `shoulder_a`, link 1 has an `a` (axis 2 passes beside axis 1).
fn arm_strategy(shoulder_a: bool) -> impl Strategy<Value = Kinematics> {
    (
        prop::array::uniform8(-0.2..0.2f64),
        prop::array::uniform6(-180.0..180.0f64),
        prop::array::uniform3(prop::bool::ANY),
        (0.2..0.6f64, 0.15..0.5f64, -180.0..180.0f64),
    )
        .prop_map(move |(len, offsets, signs, (a2, d4, alpha6))| {
            let mut cfg = RobotConfig::prob2_default();
            let l = &mut cfg.arm.links;
            let sign = |b: bool| if b { 90.0 } else { -90.0 };
            (l[0].a, l[0].d) = (if shoulder_a { len[0] } else { 0.0 }, 0.2 + len[1]);
            (l[1].a, l[1].d) = (a2, len[2]);
            (l[2].a, l[2].d, l[2].alpha_deg) = (len[3], len[4], 60.0 + 100.0 * len[5]);
            l[3].d = d4;
            (l[5].a, l[5].d, l[5].alpha_deg) = (len[6], 0.1 + len[7], alpha6);
            l[0].alpha_deg = sign(signs[0]);
            l[3].alpha_deg = sign(signs[1]);
            l[4].alpha_deg = sign(signs[2]);
            for (link, o) in l.iter_mut().zip(offsets) {
                link.offset_deg = o;
            }
            let mut k = Kinematics::from_config(&cfg).unwrap();
            k.set_ranges([WIDE; N]);
            k
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// The P-Rob2 with a tool: every solution reaches the pose and lies within the ranges;
    /// the seed's own configuration comes first; sorted by travel time.
    #[test]
    fn every_solution_reaches_the_pose(unit in unit6(), tcp in tcp_strategy()) {
        let mut k = prob2();
        k.set_tcp(tcp).unwrap();
        let q = inside(&k, unit);
        let target = k.tcp_pose(&q);
        let sols = k.inverse(&target, &q).unwrap();
        assert_all_reach(&k, &target, &sols);
        assert_first_is(&sols, &q, 1e-9);
        assert_sorted(&k, &sols, &q);
    }

    /// Without axis limits in the way, a configuration away from the singularities has eight
    /// distinct solutions, one per branch, on arms of every supported shape whose axis 2
    /// meets axis 1 (else the wrist centre may be out of reach behind axis 1).
    #[test]
    fn eight_solutions_on_every_supported_arm(k in arm_strategy(false), unit in unit6(), seed_unit in unit6()) {
        let q: [f64; N] = core::array::from_fn(|i| -PI + 2.0 * PI * unit[i]);
        prop_assume!(!k.singularities(&q).near(&SingularityMarginsTiny::M).any());
        let target = k.tcp_pose(&q);
        let seed: [f64; N] = core::array::from_fn(|i| -PI + 2.0 * PI * seed_unit[i]);
        let sols = k.inverse(&target, &seed).unwrap();
        prop_assert_eq!(sols.len(), MAX_SOLUTIONS, "{:?}", sols);
        assert_all_reach(&k, &target, &sols);
        assert_sorted(&k, &sols, &seed);
        for (i, a) in sols.iter().enumerate() {
            for b in &sols[i + 1..] {
                prop_assert_ne!(a.branch, b.branch);
            }
        }
        // The original configuration is among them (up to whole turns).
        let sols = k.inverse(&target, &q).unwrap();
        assert_first_is(&sols, &q, 1e-9);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Every solution's branch is the one `branch` names for its configuration, and
    /// `inverse_branch` of that branch gives the solution back (up to whole turns, continued
    /// from a seed nearby), on arms of every supported shape.
    #[test]
    fn each_branch_is_named_and_solved_alone(k in arm_strategy(true), unit in unit6(), seed_unit in unit6()) {
        let q: [f64; N] = core::array::from_fn(|i| -PI + 2.0 * PI * unit[i]);
        prop_assume!(!k.singularities(&q).near(&SingularityMarginsTiny::M).any());
        let target = k.tcp_pose(&q);
        let seed: [f64; N] = core::array::from_fn(|i| -PI + 2.0 * PI * seed_unit[i]);
        let Ok(sols) = k.inverse(&target, &seed) else {
            return Ok(());
        };
        for s in &sols {
            prop_assert_eq!(k.branch(&s.q), s.branch, "{:?}", s);
            let near: [f64; N] = core::array::from_fn(|i| s.q[i] + 0.3 * (seed_unit[i] - 0.5));
            let alone = k.inverse_branch(&target, s.branch, &near).unwrap();
            for (a, b) in alone.iter().zip(&s.q) {
                prop_assert!((a - b).abs() < 1e-9, "{:?} vs {:?}", alone, s.q);
            }
        }
    }
}

/// Margins small enough that only near-exact singularities are skipped.
struct SingularityMarginsTiny;
impl SingularityMarginsTiny {
    const M: crate::SingularityMargins = crate::SingularityMargins {
        wrist_rad: 1e-3,
        elbow_rad: 1e-3,
        shoulder_m: 1e-3,
    };
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// On arms of every supported shape, a shoulder offset included, every solution reaches
    /// the pose and the configuration the pose came from is found.
    #[test]
    fn every_supported_arm_is_solved(k in arm_strategy(true), unit in unit6()) {
        let q: [f64; N] = core::array::from_fn(|i| -PI + 2.0 * PI * unit[i]);
        prop_assume!(!k.singularities(&q).near(&SingularityMarginsTiny::M).any());
        let target = k.tcp_pose(&q);
        let sols = k.inverse(&target, &q).unwrap();
        prop_assert!(sols.len() >= 4, "{:?}", sols);
        assert_all_reach(&k, &target, &sols);
        assert_first_is(&sols, &q, 1e-9);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Near each singularity (within 1e-6 rad of it, or exactly on it) there are solutions
    /// and every one reaches the pose, though the joints the singularity frees are
    /// ill-conditioned there.
    #[test]
    fn near_singular_poses_are_solved(
        unit in unit6(),
        which in 0..3usize,
        near in prop::sample::select(vec![0.0, 1e-12, -1e-9, 1e-6]),
        tcp in tcp_strategy(),
    ) {
        let mut k = prob2();
        k.set_tcp(tcp).unwrap();
        let mut q = inside(&k, unit);
        match which {
            0 => q[4] = near,
            1 => q[2] = near,
            _ => {
                // The wrist centre (nearly) on axis 1: the forearm back over it.
                let up = q[1] + PI / 2.0;
                let c = (0.35 * up.cos() / -0.305).clamp(-1.0, 1.0);
                q[2] = c.acos() - up + near;
            }
        }
        prop_assume!(k.ranges().iter().zip(&q).all(|(r, v)| (r.min..=r.max).contains(v)));
        let target = k.tcp_pose(&q);
        let sols = k.inverse(&target, &q).unwrap();
        assert_all_reach(&k, &target, &sols);
        let (dp, dr) = pose_error(&k.tcp_pose(&sols[0].q), &target);
        prop_assert!(dp < 1e-9 && dr < 1e-9);
    }
}

#[test]
fn branches_are_named_as_documented() {
    let k = prob2();
    // Reaching forward, elbow up, wrist bent positively.
    let q = [0.0, -30.0, -90.0, 0.0, 30.0, 0.0].map(f64::to_radians);
    let sols = k.inverse(&k.tcp_pose(&q), &q).unwrap();
    assert_eq!(
        sols[0].branch,
        Branch {
            shoulder: Side::Positive,
            elbow: Side::Negative,
            wrist: Side::Positive
        }
    );
}

/// At each singularity the seed's configuration still comes back first, the free joint
/// keeping the seed's value, and every solution reaches the pose.
#[test]
fn singular_configurations_are_solved() {
    let mut k = prob2();
    k.set_tcp(Isometry3::translation(0.02, 0.0, 0.1)).unwrap();
    let d = f64::to_radians;
    // The forearm (0.305 m) from the elbow back to above axis 1: cos of its angle from the
    // horizontal is 0.35 cos 120° / -0.305; q3 is its angle from the upper arm.
    let shoulder_q3 = (0.35 * d(120.0).cos() / -0.305).acos() - d(120.0);
    for q in [
        // Wrist: θ5 = 0.
        [d(10.0), d(20.0), d(-40.0), d(35.0), 0.0, d(-20.0)],
        // Elbow stretched (φ = q3 = 0).
        [d(10.0), d(20.0), 0.0, d(35.0), d(50.0), d(-20.0)],
        // Shoulder: upright, the wrist centre on axis 1 (and the wrist singular too).
        [d(25.0), 0.0, 0.0, d(-30.0), 0.0, d(40.0)],
        // Shoulder only: the wrist centre on axis 1 (upper arm at 120° from the horizontal,
        // the forearm back over axis 1), the wrist bent.
        [d(-40.0), d(30.0), shoulder_q3, d(10.0), d(45.0), d(5.0)],
    ] {
        if q[2] == shoulder_q3 {
            assert!(
                k.singularities(&q).shoulder_m < 1e-12,
                "{:?}",
                k.singularities(&q)
            );
        }
        let target = k.tcp_pose(&q);
        let sols = k.inverse(&target, &q).unwrap();
        assert_all_reach(&k, &target, &sols);
        // At the elbow singularity the angle comes from an arc cosine near 1: rounding of
        // 1e-16 in the pose is 1e-8 rad there (the pose itself is met to 1e-9).
        assert_first_is(&sols, &q, 1e-7);
    }
}

#[test]
fn unreachable_poses_are_refused_saying_why() {
    let k = prob2();
    let far = Isometry3::translation(1.5, 0.0, 0.3);
    let err = k.inverse(&far, &[0.0; N]).unwrap_err();
    assert!(matches!(err, IkError::OutOfReach { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("from axis 2") && msg.contains("to 0.655 m"),
        "{msg}"
    );

    let nan = Isometry3::translation(f64::NAN, 0.0, 0.3);
    assert_eq!(
        k.inverse(&nan, &[0.0; N]).unwrap_err().to_string(),
        "the target position has NaN; it needs finite numbers"
    );
    let seed = [0.0, 0.0, f64::INFINITY, 0.0, 0.0, 0.0];
    assert!(matches!(
        k.inverse(&Isometry3::identity(), &seed),
        Err(IkError::NotFinite { what: "seed", .. })
    ));
}

/// A pose the arm reaches only with an axis beyond its range: refused naming the axis.
#[test]
fn a_pose_outside_the_axis_limits_is_refused_naming_the_axis() {
    let mut k = prob2();
    let mut ranges = *k.ranges();
    // Axis 5 may only bend positively by 10 to 60 degrees.
    ranges[4] = AxisRange {
        min: 10f64.to_radians(),
        max: 60f64.to_radians(),
    };
    let q = [0.3, 0.2, -0.5, 0.0, 0.0, 0.0];
    let target = k.tcp_pose(&q);
    k.set_ranges(ranges);
    let err = k.inverse(&target, &q).unwrap_err();
    let IkError::OutsideLimits { found, axis, .. } = err else {
        panic!("{err:?}");
    };
    assert!(found >= 4, "{err:?}");
    assert_eq!(axis, 5, "{err}");
    assert!(err.to_string().contains("outside 10 to 60 deg"), "{err}");
}

/// The count and position of the solutions do not depend on anything but the pose and the
/// seed: solving twice gives the same.
#[test]
fn solving_is_deterministic() {
    let k = prob2();
    let q = [0.1, 0.2, -0.3, 0.4, 0.5, 0.6];
    let t = k.tcp_pose(&q);
    assert_eq!(k.inverse(&t, &q), k.inverse(&t, &q));
}
