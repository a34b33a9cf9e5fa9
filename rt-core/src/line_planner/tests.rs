use super::*;
use crate::params::JointParams;
use mcm_shared::config::RobotConfig;
use nalgebra::Vector3;
use std::time::Instant;

/// A job for a 10 cm line along x from a comfortable pose of the P-Rob2.
fn job(id: u64, dx: f64) -> (LineJob, JointLimits) {
    let cfg = RobotConfig::prob2_default();
    let kin = Kinematics::from_config(&cfg).unwrap();
    let start = [0.1, 0.4, -0.3, 0.2, 0.9, -0.5];
    let p = kin.tcp_pose(&start).translation.vector;
    let request = LineRequest {
        id,
        start,
        target: LineTarget {
            position: p + Vector3::new(dx, 0.0, 0.0),
            orientation: None,
            velocity: None,
            acceleration: None,
        },
    };
    let limits = joint_limits(&JointParams::from_config(&cfg));
    (LineJob { request, kin }, limits)
}

/// The planner's result, waiting at most 5 s for it.
fn wait(planner: &LinePlanner) -> Planned {
    let t0 = Instant::now();
    loop {
        if let Some(p) = planner.finished() {
            return p.clone();
        }
        assert!(t0.elapsed().as_secs() < 5, "no plan within 5 s");
        std::thread::yield_now();
    }
}

#[test]
fn the_inline_planner_answers_at_once_and_takes_one_job_at_a_time() {
    let (j, limits) = job(1, 0.1);
    let mut planner = LinePlanner::inline(limits);
    assert!(planner.finished().is_none());
    assert!(planner.post(&j));
    let done = planner.finished().unwrap();
    assert_eq!(done.id, 1);
    let plan = done.result.as_ref().unwrap();
    assert!(plan.duration() > 0.0);
    // Its result not released yet: the next job waits.
    let (j2, _) = job(2, 0.05);
    assert!(!planner.post(&j2));
    planner.release();
    assert!(planner.finished().is_none());
    assert!(planner.post(&j2));
    assert_eq!(planner.finished().unwrap().id, 2);
}

#[test]
fn the_thread_plans_what_the_inline_planner_plans() {
    let (j, limits) = job(7, 0.1);
    let mut inline = LinePlanner::inline(limits);
    assert!(inline.post(&j));
    let expected = inline.finished().unwrap().clone();
    let mut thread = LinePlanner::thread(limits).unwrap();
    assert!(thread.post(&j));
    // Busy (planning, or done and not released): a second job waits.
    let (j2, _) = job(8, 3.0);
    assert!(!thread.post(&j2));
    let got = wait(&thread);
    assert_eq!(got.id, expected.id);
    assert_eq!(got.result, expected.result);
    thread.release();
    // A refusal comes back the same way: 3 m away is beyond the reach.
    assert!(thread.post(&j2));
    let refused = wait(&thread);
    assert_eq!(refused.id, 8);
    assert!(refused.result.is_err());
    thread.release();
}
