//! The per-call functions allocate nothing (they may run in the control cycle): a counting
//! global allocator ([`mcm_shared::alloc_count`]) counts the allocations of forward and inverse
//! kinematics, the Jacobian and the singularity measures, on reachable, unreachable and
//! singular poses, and of an IK error's construction.

use mcm_kinematics::Kinematics;
use mcm_shared::alloc_count::{self, CountingAlloc};
use mcm_shared::config::RobotConfig;
use nalgebra::Isometry3;
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
