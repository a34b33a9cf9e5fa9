//! The per-call functions allocate nothing (they may run in the control cycle): a counting
//! global allocator ([`mcm_shared::alloc_count`]) counts the allocations of forward and inverse
//! kinematics, the Jacobian and the singularity measures, on reachable, unreachable and
//! singular poses, and of an IK error's construction; and of planning straight lines (one
//! planned, one refused) and sampling one at every cycle of its duration.

use mcm_kinematics::{JointLimits, Kinematics, LinePlan, LineTarget};
use mcm_shared::alloc_count::{self, CountingAlloc};
use mcm_shared::config::RobotConfig;
use nalgebra::{Isometry3, Vector3};
use std::hint::black_box;

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

#[test]
fn kinematics_allocate_nothing() {
    let mut kin = Kinematics::from_config(&RobotConfig::prob2_default()).unwrap();
    let configurations = [
        [0.3, 0.4, -0.9, 0.2, 0.7, -0.1],
        [0.0; 6],
        [0.1, 0.2, 0.0, 0.3, 0.0, 0.4],
    ];
    let (solved, counts) = alloc_count::count(|| {
        kin.set_tcp(Isometry3::translation(0.0, 0.02, 0.15))
            .unwrap();
        let mut solved = 0;
        for q in &configurations {
            let pose = kin.tcp_pose(black_box(q));
            black_box(kin.flange_pose(q));
            black_box(kin.tcp_jacobian(q));
            black_box(kin.singularities(q));
            solved += kin.inverse(&pose, q).map_or(0, |s| s.len());
        }
        let far = Isometry3::translation(2.0, 0.0, 0.0);
        assert!(kin.inverse(&far, &configurations[0]).is_err());
        solved
    });
    assert!(solved >= 3, "every pose solved: {solved} solutions");
    assert_eq!(counts.allocations, 0, "{counts:?}");
}

#[test]
fn planning_and_sampling_a_line_allocate_nothing() {
    let cfg = RobotConfig::prob2_default();
    let mut kin = Kinematics::from_config(&cfg).unwrap();
    kin.set_tcp(Isometry3::translation(0.0, 0.0, 0.15)).unwrap();
    let limits = JointLimits::from_config(&cfg).unwrap();
    let start = [0.17, -0.52, -1.4, 0.35, 0.8, 0.17];
    let p0 = kin.tcp_pose(&start).translation.vector;
    let line = |d: Vector3<f64>| LineTarget {
        position: p0 + d,
        orientation: None,
        velocity: Some(0.25),
        acceleration: None,
    };
    let ((cycles, refused), counts) = alloc_count::count(|| {
        let plan = LinePlan::plan(&kin, &limits, &start, &line(Vector3::new(0.0, 0.09, -0.12)));
        let plan = plan.unwrap();
        let mut cycles = 0;
        let mut t = 0.0;
        while t <= plan.duration() + 0.005 {
            black_box(plan.sample(black_box(t)));
            t += 0.005;
            cycles += 1;
        }
        let far = LinePlan::plan(&kin, &limits, &start, &line(Vector3::new(2.0, 0.0, 0.0)));
        (cycles, far.is_err())
    });
    assert!(
        cycles > 100 && refused,
        "{cycles} cycles, refused: {refused}"
    );
    assert_eq!(counts.allocations, 0, "{counts:?}");
}
