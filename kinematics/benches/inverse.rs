//! Benchmark of the inverse kinematics (criterion, then the percentiles of single calls).
//!
//! ```sh
//! cargo bench -p mcm-kinematics --bench inverse
//! ```
//!
//! - `inverse/prob2_tcp`: [`Kinematics::inverse`] of the P-Rob2 with a 15 cm TCP, for poses of
//!   random configurations within the axes' reachable ranges (a new one each iteration, from
//!   1000), seeded with a configuration nearby: every solution, sorted;
//! - `forward/tcp_pose`, `forward/tcp_jacobian`: the forward kinematics and the Jacobian.
//!
//! Then 200,000 single calls of `inverse`, each timed on its own, and their p50, p99 and
//! maximum (the target: p99 at most 20 µs). Results: `docs/performance.md`.

use criterion::{Criterion, criterion_group};
use mcm_kinematics::Kinematics;
use mcm_shared::config::RobotConfig;
use nalgebra::Isometry3;
use proptest::prelude::Rng;
use proptest::test_runner::{RngAlgorithm, TestRng};
use std::hint::black_box;
use std::time::Instant;

const POSES: usize = 1000;
const TIMED_CALLS: usize = 200_000;

/// A TCP pose to solve for, and the seed.
type Case = (Isometry3<f64>, [f64; 6]);

/// The P-Rob2 with a 15 cm TCP, and `POSES` cases.
fn cases() -> (Kinematics, Vec<Case>) {
    let mut kin = Kinematics::from_config(&RobotConfig::prob2_default()).unwrap();
    kin.set_tcp(Isometry3::translation(0.0, 0.0, 0.15)).unwrap();
    let mut rng = TestRng::from_seed(RngAlgorithm::ChaCha, &[41; 32]);
    let mut unit = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let cases = (0..POSES)
        .map(|_| {
            let q: [f64; 6] = core::array::from_fn(|i| {
                let r = kin.ranges()[i];
                r.min + (r.max - r.min) * unit()
            });
            let seed = q.map(|v| v + 0.1 * (unit() - 0.5));
            (kin.tcp_pose(&q), seed)
        })
        .collect();
    (kin, cases)
}

fn benches(c: &mut Criterion) {
    let (kin, cases) = cases();
    let mut i = 0;
    c.bench_function("inverse/prob2_tcp", |b| {
        b.iter(|| {
            let (pose, seed) = &cases[i % POSES];
            i += 1;
            kin.inverse(black_box(pose), black_box(seed))
        })
    });
    let q = [0.3, 1.2, -0.7, 0.4, 0.9, -0.2];
    c.bench_function("forward/tcp_pose", |b| {
        b.iter(|| kin.tcp_pose(black_box(&q)))
    });
    c.bench_function("forward/tcp_jacobian", |b| {
        b.iter(|| kin.tcp_jacobian(black_box(&q)))
    });
}

/// Each call timed on its own: the percentiles criterion's mean does not give.
fn percentiles() {
    let (kin, cases) = cases();
    let mut ns = Vec::with_capacity(TIMED_CALLS);
    let mut solutions = 0usize;
    for i in 0..TIMED_CALLS {
        let (pose, seed) = &cases[i % POSES];
        let t = Instant::now();
        let r = kin.inverse(black_box(pose), black_box(seed));
        ns.push(t.elapsed().as_nanos() as u64);
        solutions += r.map_or(0, |s| s.len());
    }
    ns.sort_unstable();
    let at = |p: f64| ns[((ns.len() as f64 * p) as usize).min(ns.len() - 1)] as f64 / 1000.0;
    println!(
        "inverse/prob2_tcp single calls: n {TIMED_CALLS}, p50 {:.2} us, p99 {:.2} us, \
         p99.9 {:.2} us, max {:.2} us ({:.2} solutions per call)",
        at(0.5),
        at(0.99),
        at(0.999),
        *ns.last().unwrap() as f64 / 1000.0,
        solutions as f64 / TIMED_CALLS as f64
    );
}

criterion_group!(group, benches);

fn main() {
    group();
    percentiles();
    Criterion::default().configure_from_args().final_summary();
}
