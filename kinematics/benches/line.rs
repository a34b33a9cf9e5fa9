//! Benchmark of the straight-line planner (criterion, then the percentiles of single calls).
//!
//! ```sh
//! cargo bench -p mcm-kinematics --bench line
//! ```
//!
//! The P-Rob2 with a 15 cm TCP pointing down:
//! - `line/plan_1m`: [`LinePlan::plan`] of a 1 m line across the front of the arm (y from
//!   −0.5 to 0.5 m at x = 0.4 m), at 0.25 m/s: 1024 points checked;
//! - `line/plan_15cm`: a 15 cm line (192 points);
//! - `line/sample`: one [`LinePlan::sample`] of the 1 m line, at a new time each iteration
//!   (what the cycle calls every 5 ms).
//!
//! Then single calls, each timed on its own: 2,000 plans of the 1 m line and 200,000 samples,
//! their p50, p99 and maximum (the target: planning a 1 m path at most 5 ms). Results:
//! `docs/performance.md`.

use criterion::{Criterion, criterion_group};
use mcm_kinematics::{JointLimits, Kinematics, LinePlan, LineTarget};
use mcm_shared::config::RobotConfig;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Instant;

/// The arm, its limits, the start of the lines and the targets of the 1 m and 15 cm lines.
fn setup() -> (Kinematics, JointLimits, [f64; 6], LineTarget, LineTarget) {
    let cfg = RobotConfig::prob2_default();
    let mut kin = Kinematics::from_config(&cfg).unwrap();
    kin.set_tcp(Isometry3::translation(0.0, 0.0, 0.15)).unwrap();
    let limits = JointLimits::from_config(&cfg).unwrap();
    let down = UnitQuaternion::from_euler_angles(PI, 0.0, 0.0);
    let from = Isometry3::from_parts(Translation3::new(0.4, -0.5, 0.1), down);
    let seed = [-0.9, -0.3, -1.6, 0.0, -1.2, 0.0];
    let start = kin.inverse(&from, &seed).unwrap()[0].q;
    let line = |to: Vector3<f64>| LineTarget {
        position: to,
        orientation: None,
        velocity: Some(0.25),
        acceleration: None,
    };
    let long = line(Vector3::new(0.4, 0.5, 0.1));
    let short = line(Vector3::new(0.4, -0.35, 0.1));
    (kin, limits, start, long, short)
}

fn benches(c: &mut Criterion) {
    let (kin, limits, start, long, short) = setup();
    c.bench_function("line/plan_1m", |b| {
        b.iter(|| LinePlan::plan(&kin, &limits, black_box(&start), black_box(&long)))
    });
    c.bench_function("line/plan_15cm", |b| {
        b.iter(|| LinePlan::plan(&kin, &limits, black_box(&start), black_box(&short)))
    });
    let plan = LinePlan::plan(&kin, &limits, &start, &long).unwrap();
    let mut k = 0u32;
    c.bench_function("line/sample", |b| {
        b.iter(|| {
            k = k.wrapping_add(1);
            plan.sample(black_box(f64::from(k % 1000) / 1000.0 * plan.duration()))
        })
    });
}

/// p50, p99, max [µs] of `n` single calls of `call`.
fn percentiles(name: &str, n: usize, mut call: impl FnMut(usize)) {
    let mut ns = Vec::with_capacity(n);
    for i in 0..n {
        let t = Instant::now();
        call(i);
        ns.push(t.elapsed().as_nanos() as u64);
    }
    ns.sort_unstable();
    let at = |p: f64| ns[((n as f64 * p) as usize).min(n - 1)] as f64 / 1000.0;
    println!(
        "{name} single calls: n {n}, p50 {:.2} us, p99 {:.2} us, max {:.2} us",
        at(0.5),
        at(0.99),
        *ns.last().unwrap() as f64 / 1000.0
    );
}

criterion_group!(group, benches);

fn main() {
    let (kin, limits, start, long, _) = setup();
    let plan = LinePlan::plan(&kin, &limits, &start, &long).unwrap();
    println!(
        "the 1 m line: {:.3} s, joint target {:?}",
        plan.duration(),
        plan.joint_target()
    );
    group();
    percentiles("line/plan_1m", 2000, |_| {
        black_box(LinePlan::plan(&kin, &limits, black_box(&start), &long)).unwrap();
    });
    percentiles("line/sample", 200_000, |i| {
        black_box(plan.sample(black_box((i % 1000) as f64 / 1000.0 * plan.duration())));
    });
    Criterion::default().configure_from_args().final_summary();
}
