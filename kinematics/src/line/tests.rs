//! The straight-line planner: every 200 Hz sample on the line and the arc, within the TCP's
//! requested speed and every axis's limits (finite differences), at the target at the end;
//! paths through unreachable, singular or out-of-range regions refused naming where.

use super::check::between_for_test;
use super::*;
use crate::tests::{inside, pose_error, prob2, unit6};
use crate::{IkError, SingularityMargins};
use mcm_shared::error_code::ErrorCode;
use proptest::prelude::*;

const DT: f64 = 0.005;
const D: fn(f64) -> f64 = f64::to_radians;

fn limits() -> JointLimits {
    JointLimits::from_config(&RobotConfig::prob2_default()).unwrap()
}

fn to(position: Vector3<f64>) -> LineTarget {
    LineTarget {
        position,
        orientation: None,
        velocity: None,
        acceleration: None,
    }
}

/// What the samples of a plan showed.
#[derive(Debug)]
struct Seen {
    peak_speed: f64,
    /// The largest share of each limit seen (velocity, acceleration, jerk) over the axes.
    peak_share: [f64; 3],
}

/// Sample `plan` at 200 Hz over its whole duration and check every sample against the line,
/// the arc, the requested speed (5 %) and every axis's limits (finite differences: the
/// difference quotients are averages of the derivative over a few samples, so they may not
/// exceed the limits; 1 % is allowed for rounding), and the end against the target.
fn check_samples(kin: &Kinematics, start: &[f64; N], target: &LineTarget, plan: &LinePlan) -> Seen {
    let lim = limits();
    let p0 = kin.tcp_pose(start);
    let r1 = target.orientation.unwrap_or(p0.rotation);
    let dir = target.position - p0.translation.vector;
    let length = dir.norm();
    let turn = (p0.rotation.inverse() * r1).scaled_axis();
    let velocity = target.velocity.unwrap_or(DEFAULT_VELOCITY_M_S);
    let steps = (plan.duration() / DT).ceil() as usize;
    let qs: Vec<[f64; N]> = (0..=steps + 3)
        .map(|k| plan.sample(k as f64 * DT).q)
        .collect();
    let mut seen = Seen {
        peak_speed: 0.0,
        peak_share: [0.0; 3],
    };
    for (k, q) in qs.iter().enumerate() {
        let pose = kin.tcp_pose(q);
        let p = pose.translation.vector - p0.translation.vector;
        // On the line: the distance from it, and the fraction along it.
        let along = if length > 0.0 {
            p.dot(&dir) / length
        } else {
            0.0
        };
        let off = (p - along * dir / length.max(f64::MIN_POSITIVE)).norm();
        assert!(off < 1e-6, "sample {k}: {off} m off the line");
        assert!(
            along > -1e-9 && along < length + 1e-9,
            "sample {k}: {along} of {length}"
        );
        // On the arc: at the fraction of the way the position is at (or s, for a pure turn).
        let s = if length > 1e-9 {
            along / length
        } else {
            plan.path_at(k as f64 * DT).0
        };
        let on_arc = p0.rotation * UnitQuaternion::from_scaled_axis(s * turn);
        let err = pose.rotation.angle_to(&on_arc);
        assert!(err < 1e-6, "sample {k}: {err} rad off the arc");
        let sample = plan.sample(k as f64 * DT);
        for i in 0..N {
            let share = sample.qdot[i].abs() / lim.velocity[i];
            assert!(
                share <= 1.01,
                "sample {k} axis {}: qdot {share} of the limit",
                i + 1
            );
        }
    }
    let d = |k: usize, i: usize, order: usize| match order {
        1 => (qs[k + 1][i] - qs[k][i]) / DT,
        2 => (qs[k + 2][i] - 2.0 * qs[k + 1][i] + qs[k][i]) / (DT * DT),
        _ => (qs[k + 3][i] - 3.0 * qs[k + 2][i] + 3.0 * qs[k + 1][i] - qs[k][i]) / (DT * DT * DT),
    };
    for k in 0..qs.len() - 3 {
        let a = kin.tcp_pose(&qs[k]).translation.vector;
        let b = kin.tcp_pose(&qs[k + 1]).translation.vector;
        let speed = (b - a).norm() / DT;
        seen.peak_speed = seen.peak_speed.max(speed);
        assert!(
            speed <= 1.05 * velocity,
            "sample {k}: TCP at {speed} m/s, asked {velocity}"
        );
        for i in 0..N {
            let caps = [
                lim.velocity[i],
                lim.acceleration[i],
                lim.jerk[i].unwrap_or(f64::INFINITY),
            ];
            for (order, cap) in (1..=3).zip(caps) {
                let share = d(k, i, order).abs() / cap;
                seen.peak_share[order - 1] = seen.peak_share[order - 1].max(share);
                assert!(
                    share <= 1.01,
                    "sample {k} axis {}: derivative {order} at {share} of its limit",
                    i + 1
                );
            }
        }
    }
    let end = kin.tcp_pose(qs.last().unwrap());
    let goal = Isometry3::from_parts(target.position.into(), r1);
    let (dp, dr) = pose_error(&end, &goal);
    assert!(
        dp < 0.5e-3 && dr < D(0.1),
        "ends {dp} m, {dr} rad from the target"
    );
    assert_eq!(*qs.last().unwrap(), plan.joint_target());
    seen
}

/// A configuration of the P-Rob2 reaching forward, away from every singularity.
const REACHING: [f64; N] = [0.17, -0.52, -1.4, 0.35, 0.8, 0.17];

#[test]
fn prob2_15cm_line_at_a_quarter_metre_per_second() {
    let kin = prob2();
    let start = REACHING;
    let p0 = kin.tcp_pose(&start).translation.vector;
    let target = LineTarget {
        velocity: Some(0.25),
        ..to(p0 + Vector3::new(0.0, 0.09, -0.12))
    };
    let plan = LinePlan::plan(&kin, &limits(), &start, &target).unwrap();
    let seen = check_samples(&kin, &start, &target, &plan);
    // It cruises at the asked speed: 15 cm at 0.25 m/s and 1.2 m/s² takes 0.6 s of cruise
    // and 2 × 0.21 s of acceleration.
    assert!(seen.peak_speed > 0.24, "{seen:?}");
    assert!(plan.duration() < 1.1, "{}", plan.duration());
    assert_eq!(plan.branch(), kin.branch(&start));
    // Its pace changes little along it: one segment, one double-S.
    assert_eq!(plan.profile.segments(), 1);
}

#[test]
fn a_turn_on_the_spot_keeps_the_tcp_and_turns_on_the_shortest_arc() {
    let kin = prob2();
    let start = REACHING;
    let p0 = kin.tcp_pose(&start);
    let turn = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.4);
    let target = LineTarget {
        orientation: Some(p0.rotation * turn),
        ..to(p0.translation.vector)
    };
    let plan = LinePlan::plan(&kin, &limits(), &start, &target).unwrap();
    check_samples(&kin, &start, &target, &plan);
    // The angular speed stays within the request over the rotation radius.
    let (mut t, mut peak) = (0.0, 0.0f64);
    while t < plan.duration() {
        let a = kin.tcp_pose(&plan.sample(t).q).rotation;
        let b = kin.tcp_pose(&plan.sample(t + DT).q).rotation;
        peak = peak.max(a.angle_to(&b) / DT);
        t += DT;
    }
    assert!(
        peak <= 1.05 * DEFAULT_VELOCITY_M_S / ROTATION_RADIUS_M,
        "{peak} rad/s"
    );
}

#[test]
fn a_line_with_a_turn_at_full_speed_stays_within_every_limit() {
    let kin = prob2();
    let start = REACHING;
    let p0 = kin.tcp_pose(&start);
    let target = LineTarget {
        position: p0.translation.vector + Vector3::new(-0.1, 0.15, 0.05),
        orientation: Some(p0.rotation * UnitQuaternion::from_euler_angles(0.0, 0.4, -0.3)),
        velocity: Some(MAX_VELOCITY_M_S),
        acceleration: Some(MAX_ACCELERATION_M_S2),
    };
    let plan = LinePlan::plan(&kin, &limits(), &start, &target).unwrap();
    let seen = check_samples(&kin, &start, &target, &plan);
    // An axis's limit, not the request, sets the pace here: some axis comes near a limit.
    assert!(seen.peak_share.iter().any(|s| *s > 0.5), "{seen:?}");
}

/// A turn about the flange's axis moves axis 6 alone, linearly along the path: asked at the
/// planner's most, axis 6's limits set the pace, and the move reaches them.
#[test]
fn a_turn_about_the_flange_axis_is_paced_by_axis_6() {
    let kin = prob2();
    let p0 = kin.tcp_pose(&REACHING);
    let target = LineTarget {
        position: p0.translation.vector,
        orientation: Some(p0.rotation * UnitQuaternion::from_euler_angles(0.0, 0.0, -3.0)),
        velocity: Some(MAX_VELOCITY_M_S),
        acceleration: Some(MAX_ACCELERATION_M_S2),
    };
    let plan = LinePlan::plan(&kin, &limits(), &REACHING, &target).unwrap();
    let seen = check_samples(&kin, &REACHING, &target, &plan);
    assert!(seen.peak_share[0] > 0.95, "{seen:?}");
    assert!((plan.joint_target()[5] - REACHING[5] + 3.0).abs() < 1e-9);
}

#[test]
fn no_motion_is_a_plan_of_no_time() {
    let kin = prob2();
    let p0 = kin.tcp_pose(&REACHING).translation.vector;
    let plan = LinePlan::plan(&kin, &limits(), &REACHING, &to(p0)).unwrap();
    assert_eq!(plan.duration(), 0.0);
    for q in [plan.sample(0.0).q, plan.joint_target()] {
        assert!(
            q.iter().zip(&REACHING).all(|(a, b)| (a - b).abs() < 1e-12),
            "{q:?}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Random lines from random configurations of the P-Rob2 with a tool: every plan passes
    /// the samples' checks; every refusal is one of the path's, naming a point on the line.
    #[test]
    fn every_plan_keeps_to_the_line_and_the_limits(
        unit in unit6(),
        step in prop::array::uniform3(-0.2..0.2f64),
        rpy in prop::array::uniform3(-0.5..0.5f64),
        turn in any::<bool>(),
        speed in 0.05..1.0f64,
        tool in 0.0..0.2f64,
    ) {
        let mut kin = prob2();
        kin.set_tcp(Isometry3::translation(0.0, 0.0, tool)).unwrap();
        let start = inside(&kin, unit.map(|u| 0.1 + 0.8 * u));
        prop_assume!(!kin.singularities(&start).near(&SingularityMargins::DEFAULT).any());
        let p0 = kin.tcp_pose(&start);
        let target = LineTarget {
            position: p0.translation.vector + Vector3::from(step),
            orientation: turn.then(|| {
                p0.rotation * UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2])
            }),
            velocity: Some(speed),
            acceleration: None,
        };
        match LinePlan::plan(&kin, &limits(), &start, &target) {
            Ok(plan) => {
                check_samples(&kin, &start, &target, &plan);
            }
            Err(e) => {
                let at = e.at().unwrap_or_else(|| panic!("{e}"));
                prop_assert!((0.0..=1.0).contains(&at.fraction), "{}", e);
                let on = p0.translation.vector + at.fraction * Vector3::from(step);
                let off = (Vector3::from(at.position) - on).norm();
                prop_assert!(off < 1e-9, "{}", e);
            }
        }
    }
}

/// How far along `from` → `to` (a fraction) a predicate first holds, to 1e-6.
fn first_fraction(holds: impl Fn(f64) -> bool) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    while hi - lo > 1e-6 {
        let mid = (lo + hi) / 2.0;
        if holds(mid) { hi = mid } else { lo = mid }
    }
    hi
}

/// The start's branch at the fraction `s` of the line from `from` along `d`, the orientation
/// `r` kept.
fn on_line(
    kin: &Kinematics,
    start: &[f64; N],
    (from, d, r): (Vector3<f64>, Vector3<f64>, UnitQuaternion<f64>),
    s: f64,
) -> Result<[f64; N], IkError> {
    let pose = Isometry3::from_parts((from + s * d).into(), r);
    kin.inverse_branch(&pose, kin.branch(start), start)
}

/// The spacing of the checked points, as a fraction of a line of `length` metres.
fn spacing(length: f64) -> f64 {
    let n = ((length / STEP_M / KNOTS as f64).ceil() as usize * KNOTS).min(MAX_INTERVALS);
    1.0 / n as f64
}

#[test]
fn a_line_out_of_reach_is_refused_where_it_leaves_the_workspace() {
    let kin = prob2();
    let p0 = kin.tcp_pose(&REACHING).translation.vector;
    let target = to(p0 + Vector3::new(0.8, 0.0, 0.0));
    let err = LinePlan::plan(&kin, &limits(), &REACHING, &target).unwrap_err();
    assert_eq!(err.error_code(), ErrorCode::Unreachable, "{err}");
    // The elbow's margin is met just before the reach ends (or the reach itself).
    let at = err.at().unwrap();
    let r0 = kin.tcp_pose(&REACHING).rotation;
    let reach_ends = first_fraction(|s| {
        let pose = Isometry3::from_parts((p0 + s * Vector3::new(0.8, 0.0, 0.0)).into(), r0);
        kin.inverse_branch(&pose, kin.branch(&REACHING), &REACHING)
            .is_err()
    });
    assert!(
        at.fraction <= reach_ends + spacing(0.8) && at.fraction > reach_ends - 0.02,
        "{err}: the reach ends at {reach_ends}"
    );
    assert!(
        matches!(
            err,
            LineError::Singular {
                singularity: Singularity::Elbow,
                ..
            } | LineError::Unreachable {
                cause: IkError::OutOfReach { .. },
                ..
            }
        ),
        "{err}"
    );
    assert!(
        err.to_string().contains("% of the path (the TCP at ["),
        "{err}"
    );
}

/// A line through a pose where axes 4 and 6 align (θ5 = 0) is refused at the wrist's margin.
#[test]
fn a_line_through_the_wrist_singularity_is_refused() {
    let kin = prob2();
    let singular = [0.17, -0.52, -1.4, 0.35, 0.0, 0.17];
    let mid = kin.tcp_pose(&singular);
    let step = Vector3::new(0.0, 0.1, 0.0);
    let start_pose = Isometry3::from_parts((mid.translation.vector - step).into(), mid.rotation);
    let seed = [0.17, -0.52, -1.4, 0.35, 0.3, 0.17];
    let start = kin.inverse(&start_pose, &seed).unwrap()[0].q;
    assert!(
        !kin.singularities(&start)
            .near(&SingularityMargins::DEFAULT)
            .any()
    );
    let target = to(mid.translation.vector + step);
    let err = LinePlan::plan(&kin, &limits(), &start, &target).unwrap_err();
    let LineError::Singular {
        at,
        singularity: Singularity::Wrist,
        value,
        margin,
    } = err
    else {
        panic!("{err}");
    };
    assert_eq!(err.error_code(), ErrorCode::Unreachable);
    assert!(at.fraction > 0.1 && at.fraction < 0.5, "{err}");
    assert!(value < margin && margin == 5.0, "{err}");
    // The point named is where the measure falls below the margin, within one spacing.
    let line = (start_pose.translation.vector, 2.0 * step, mid.rotation);
    let below = first_fraction(|s| {
        let q = on_line(&kin, &start, line, s).unwrap();
        kin.singularities(&q).wrist_rad < D(5.0)
    });
    assert!(
        (at.fraction - below).abs() <= spacing(0.2),
        "{err}: below from {below}"
    );
}

/// A line passing over the base, the wrist centre across axis 1, is refused at the
/// shoulder's margin.
#[test]
fn a_line_over_the_base_is_refused_at_the_shoulder() {
    let kin = prob2();
    let start = [0.0, -0.3, -1.2, 0.2, 0.9, 0.0];
    let p0 = kin.tcp_pose(&start).translation.vector;
    // The wrist centre moves as the TCP does (the orientation kept): to its mirror image
    // across axis 1, on axis 1 half-way.
    let c = kin.frames(&start).origin[3];
    let target = to(p0 - 2.0 * Vector3::new(c.x, c.y, 0.0));
    let err = LinePlan::plan(&kin, &limits(), &start, &target).unwrap_err();
    assert!(
        matches!(
            err,
            LineError::Singular {
                singularity: Singularity::Shoulder,
                ..
            }
        ),
        "{err}"
    );
    let at = err.at().unwrap();
    assert!(at.fraction > 0.2 && at.fraction < 0.5, "{err}");
}

/// A line that would turn axis 1 past its reachable range is refused naming axis 1, its value
/// and the range, where the axis crosses the range's bound.
#[test]
fn a_line_out_of_an_axis_range_is_refused_naming_the_axis() {
    let kin = prob2();
    let start = [D(160.0), -0.52, -1.4, 0.35, 0.8, 0.17];
    let p0 = kin.tcp_pose(&start).translation.vector;
    // Sideways, turning axis 1 further positive.
    let side = Vector3::new(-p0.y, p0.x, 0.0).normalize() * 0.25;
    let target = to(p0 + side);
    let err = LinePlan::plan(&kin, &limits(), &start, &target).unwrap_err();
    let LineError::OutOfRange {
        at,
        axis: 1,
        value_deg,
        max_deg,
        ..
    } = err
    else {
        panic!("{err}");
    };
    assert_eq!(err.error_code(), ErrorCode::OutOfRange);
    assert!(
        (max_deg - 169.0).abs() < 1e-9 && value_deg > max_deg,
        "{err}"
    );
    let line = (p0, side, kin.tcp_pose(&start).rotation);
    let crosses = first_fraction(|s| on_line(&kin, &start, line, s).unwrap()[0] > D(169.0));
    assert!(
        (at.fraction - crosses).abs() <= spacing(0.25),
        "{err}: crosses at {crosses}"
    );
}

#[test]
fn bad_requests_are_refused_naming_the_value() {
    let kin = prob2();
    let p0 = kin.tcp_pose(&REACHING).translation.vector;
    for (velocity, acceleration, name) in [
        (Some(0.0), None, "velocity"),
        (Some(1.5), None, "velocity"),
        (Some(f64::NAN), None, "velocity"),
        (None, Some(-1.0), "acceleration"),
        (None, Some(11.0), "acceleration"),
    ] {
        let target = LineTarget {
            velocity,
            acceleration,
            ..to(p0)
        };
        let err = LinePlan::plan(&kin, &limits(), &REACHING, &target).unwrap_err();
        assert!(
            matches!(err, LineError::Argument { name: n, .. } if n == name),
            "{err}"
        );
        assert_eq!(err.error_code(), ErrorCode::OutOfRange);
    }
    let err = LinePlan::plan(
        &kin,
        &limits(),
        &REACHING,
        &to(Vector3::new(f64::NAN, 0.0, 0.0)),
    );
    assert!(matches!(
        err,
        Err(LineError::NotFinite {
            what: "target position",
            ..
        })
    ));
    let msg = LinePlan::plan(
        &kin,
        &limits(),
        &REACHING,
        &LineTarget {
            velocity: Some(2.0),
            ..to(p0)
        },
    )
    .unwrap_err()
    .to_string();
    assert_eq!(
        msg,
        "move_linear velocity = 2 m/s is not allowed: it needs more than 0 and at most 1 m/s"
    );
}

/// The checks between two points: a jump, an overshoot of a turning axis beyond its range,
/// the wrist measure dipping between two points outside the margin, and the reach passing
/// the stretched elbow between them are each refused.
#[test]
fn what_lies_between_two_points_is_checked() {
    let kin = prob2();
    let h = 1.0 / 1024.0;
    let base = between_for_test::point(&kin, &REACHING, [0.1; N]);
    let ok = |b: &between_for_test::Point| between_for_test::check(&kin, &base, b, h, 1e-3);
    assert!(ok(&between_for_test::point(&kin, &REACHING, [0.1; N])).is_ok());
    // A jump of axis 4 by 90° where its rate is 0.1 per unit s.
    let mut q = REACHING;
    q[3] += D(90.0);
    let err = ok(&between_for_test::point(&kin, &q, [0.1; N])).unwrap_err();
    assert!(matches!(err, LineError::JointJump { axis: 4, .. }), "{err}");
    assert!(
        err.to_string()
            .contains("axis 4 would jump by 90 deg within 0.09765625 % of the path"),
        "{err}"
    );
    // Axis 1 at its bound, turning there fast: the overshoot is refused.
    let mut at_max = REACHING;
    at_max[0] = kin.ranges()[0].max;
    let mut rates = [0.1; N];
    rates[0] = 10.0;
    let a = between_for_test::point(&kin, &at_max, rates);
    rates[0] = -10.0;
    let b = between_for_test::point(&kin, &at_max, rates);
    let err = between_for_test::check(&kin, &a, &b, h, 1e-3).unwrap_err();
    assert!(
        matches!(err, LineError::OutOfRange { axis: 1, .. }),
        "{err}"
    );
    // θ5 at +6° at both ends, axis 5 turning at 40 rad per unit s: it passes 0 between them.
    let mut wrist = REACHING;
    wrist[4] = D(6.0);
    let mut rates = [0.1; N];
    rates[4] = -40.0;
    let a = between_for_test::point(&kin, &wrist, rates);
    rates[4] = 40.0;
    let b = between_for_test::point(&kin, &wrist, rates);
    let err = between_for_test::check(&kin, &a, &b, h, 1e-3).unwrap_err();
    assert!(
        matches!(
            err,
            LineError::Singular {
                singularity: Singularity::Wrist,
                ..
            }
        ),
        "{err}"
    );
    // The elbow 6° from stretched at both ends, the wrist centre moving 2 mm between them.
    let offset = kin.links[2].offset + kin.shape.forearm_angle;
    let mut elbow = REACHING;
    elbow[2] = D(6.0) - offset;
    let a = between_for_test::point(&kin, &elbow, [0.1; N]);
    assert!(between_for_test::check(&kin, &a, &a, h, 1e-4).is_ok());
    let err = between_for_test::check(&kin, &a, &a, h, 2e-3).unwrap_err();
    assert!(
        matches!(
            err,
            LineError::Singular {
                singularity: Singularity::Elbow,
                ..
            }
        ),
        "{err}"
    );
}

/// The time law: the duration of the closed form (V = 1, A = 2, J = 20: 0.6 s to accelerate,
/// 0.4 s of cruise), s continuous and monotonic, its rates within the bounds, exactly 1 at
/// the end; the trapezoid and the short, triangular cases too.
#[test]
fn the_time_law_keeps_its_bounds_and_ends_at_one() {
    for (v, a, j, duration) in [
        (1.0, 2.0, Some(20.0), Some(1.6)),
        (1.0, 2.0, None, Some(1.5)),
        (5.0, 2.0, Some(20.0), None),
        (5.0, 50.0, Some(20.0), None),
        (5.0, 2.0, None, None),
    ] {
        let p = profile::PathProfile::new(&[profile::Segment {
            length: 1.0,
            v,
            a,
            j: j.unwrap_or(f64::INFINITY),
        }]);
        if let Some(d) = duration {
            assert!((p.duration() - d).abs() < 1e-12, "{p:?}");
        }
        assert_eq!(p.sample(p.duration()), (1.0, 0.0, 0.0));
        let dt = p.duration() / 20_000.0;
        let mut last = p.sample(0.0);
        for k in 1..=20_000 {
            let now = p.sample(k as f64 * dt);
            assert!(now.0 >= last.0 && now.1 <= v + 1e-12 && now.2.abs() <= a + 1e-12);
            assert!(
                (now.0 - last.0 - (now.1 + last.1) / 2.0 * dt).abs() < a * dt * dt,
                "{p:?} {k}"
            );
            if let Some(j) = j {
                assert!((now.2 - last.2).abs() <= j * dt * (1.0 + 1e-9), "{p:?} {k}");
            }
            last = now;
        }
    }
}

/// The benchmark's 1 m line (`benches/line.rs`): the P-Rob2 with a 15 cm TCP pointing down,
/// y from −0.5 to 0.5 m at x = 0.4 m, z = 0.1 m, at 0.25 m/s. Its ends bring the wrist centre
/// near the edge of the reach, where the axes turn fastest per metre.
fn benchmark_line() -> (Kinematics, [f64; N], LineTarget) {
    let mut kin = prob2();
    kin.set_tcp(Isometry3::translation(0.0, 0.0, 0.15)).unwrap();
    let down = UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
    let from = Isometry3::from_parts(Vector3::new(0.4, -0.5, 0.1).into(), down);
    let seed = [-0.9, -0.3, -1.6, 0.0, -1.2, 0.0];
    let start = kin.inverse(&from, &seed).unwrap()[0].q;
    let target = LineTarget {
        velocity: Some(0.25),
        ..to(Vector3::new(0.4, 0.5, 0.1))
    };
    (kin, start, target)
}

/// The pace follows the path: the line is slow only near its hard ends, so it takes far less
/// than one pace for the whole path (the smallest bounds of every segment) would, reaches the
/// requested speed in the middle, and every sample, at the hard ends too, stays within the
/// limits; the law itself keeps each segment's bounds.
#[test]
fn the_pace_follows_the_path_near_the_edge_of_the_reach() {
    let (kin, start, target) = benchmark_line();
    let plan = LinePlan::plan(&kin, &limits(), &start, &target).unwrap();
    let uniform = plan.profile.uniform().duration();
    assert!(
        plan.duration() < uniform / 3.0,
        "{} s, one pace: {uniform} s",
        plan.duration()
    );
    let seen = check_samples(&kin, &start, &target, &plan);
    assert!(seen.peak_speed > 0.24, "{seen:?}");
    // Near the ends the axes set a pace far below the request's (0.25 per unit s, the line
    // 1 m long), the law follows it there, and the samples there are within the limits
    // (`check_samples`).
    let (end, middle) = (plan.profile.segment_at(0.01), plan.profile.segment_at(0.5));
    assert!(end.v < 0.5 * middle.v, "{end:?} {middle:?}");
    assert!(middle.v > 0.96 * 0.25, "{middle:?}");
    check_law(&plan.profile);
}

/// Sample a law finely: s monotonic from 0 to exactly 1, ṡ, s̈ and s⃛ (differences) within
/// the bounds of the segment each sample is in.
fn check_law(p: &profile::PathProfile) {
    assert_eq!(p.sample(p.duration()), (1.0, 0.0, 0.0));
    let steps = 200_000;
    let dt = p.duration() / steps as f64;
    let mut last = p.sample(0.0);
    for k in 1..=steps {
        let now = p.sample(k as f64 * dt);
        let seg = p.segment_at(now.0);
        let before = p.segment_at(last.0);
        let (v, a) = (seg.v.max(before.v), seg.a.max(before.a));
        assert!(now.0 >= last.0, "{k}: s back from {} to {}", last.0, now.0);
        assert!(now.1 <= v * (1.0 + 1e-9), "{k}: {now:?} over {seg:?}");
        assert!(now.2.abs() <= a * (1.0 + 1e-9), "{k}: {now:?} over {seg:?}");
        assert!(
            (now.0 - last.0 - (now.1 + last.1) / 2.0 * dt).abs() <= a * dt * dt,
            "{k}: {now:?} after {last:?}"
        );
        let j = seg.j.max(before.j);
        assert!(
            (now.2 - last.2).abs() <= j * dt * (1.0 + 1e-6),
            "{k}: {now:?} after {last:?}"
        );
        last = now;
    }
}

/// A path whose pace changes at every interval, back and forth by a factor of up to 100, is
/// gathered into at most `MAX_SEGMENTS` segments whose law keeps their bounds.
#[test]
fn a_restless_pace_fits_the_segments() {
    let lim = limits();
    let twist = Vector6::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let h = 1.0 / MAX_INTERVALS as f64;
    let mut pace = scaling::Pace::new(&lim, 1.0, 10.0, &twist, h).unwrap();
    for k in 0..MAX_INTERVALS {
        let rate = 0.1 + 10.0 * (k as f64 * 0.37).sin().abs();
        pace.push(&check::Bounds {
            rate: [rate; N],
            curvature: [1.0; N],
            third: [10.0; N],
        });
    }
    let law = pace.profile();
    assert!(
        law.segments() > 1 && law.segments() <= profile::MAX_SEGMENTS,
        "{}",
        law.segments()
    );
    check_law(&law);
}
