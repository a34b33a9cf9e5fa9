use super::*;
use mcm_shared::config::RobotConfig;

fn params() -> JointParams {
    JointParams::from_config(&RobotConfig::prob2_default())
}

fn point(q: f64, v: f64) -> PvtPoint {
    PvtPoint {
        position: [q; NUM_AXES],
        velocity: [v; NUM_AXES],
    }
}

#[test]
fn passes_through_every_point_at_its_time() {
    let p = params();
    let mut s = PvtStream::new();
    s.reset(0.01);
    let pts: Vec<PvtPoint> = (1..=20)
        .map(|k| {
            let t = k as f64 * 0.01;
            // p = A (1 - cos wt): starts at rest, |a| <= A w^2 = 0.9 rad/s^2.
            point(0.1 * (1.0 - (t * 3.0).cos()), 0.3 * (t * 3.0).sin())
        })
        .collect();
    s.stage(7, &pts).unwrap();
    s.commit(7, &JointSample::default(), &p).unwrap();
    assert_eq!(s.queued(), 20);
    // Period 0.005: every second cycle lands on a point.
    for k in 1..=40 {
        let (state, r) = s.advance(0.005);
        if k % 2 == 0 && k < 40 {
            let expect = pts[k / 2 - 1].position[0];
            assert!(
                (r.position[0] - expect).abs() < 1e-9,
                "k {k}: {} vs {expect}",
                r.position[0]
            );
            assert_eq!(state, StreamState::Running);
        }
    }
}

#[test]
fn a_stream_ending_in_motion_starves_and_one_ending_at_rest_finishes() {
    let p = params();
    let mut s = PvtStream::new();
    s.reset(0.01);
    // Constant acceleration of 2 rad/s^2 from rest for 10 ms.
    s.stage(1, &[point(0.0001, 0.02)]).unwrap();
    s.commit(1, &JointSample::default(), &p).unwrap();
    let (st, _) = s.advance(0.005);
    assert_eq!(st, StreamState::Running);
    let (st, _) = s.advance(0.005);
    assert!(matches!(st, StreamState::Starved(_)), "{st:?}");
    assert!(!s.running());

    s.stage(1, &[point(0.00004, 0.0)]).unwrap();
    s.commit(1, &JointSample::default(), &p).unwrap();
    s.advance(0.005);
    let (st, _) = s.advance(0.005);
    assert_eq!(st, StreamState::Finished([0.00004; NUM_AXES]));
}

#[test]
fn a_bad_point_refuses_the_whole_batch() {
    let p = params();
    let mut s = PvtStream::new();
    s.reset(0.01);
    // A jump of 1 rad in 10 ms breaks the velocity limit of the segment.
    s.stage(1, &[point(0.00004, 0.0), point(1.0, 0.0)]).unwrap();
    let e = s.commit(1, &JointSample::default(), &p).unwrap_err();
    assert!(
        matches!(
            e,
            BatchError::Point {
                index: 1,
                axis: 0,
                ..
            }
        ),
        "{e:?}"
    );
    assert_eq!(s.queued(), 0);
    // Outside the reachable range.
    s.stage(1, &[point(3.0, 0.0)]).unwrap();
    let e = s.commit(1, &JointSample::default(), &p).unwrap_err();
    assert!(
        matches!(
            e,
            BatchError::Point {
                index: 0,
                what: PvtQuantity::Position,
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn overflow_queues_nothing() {
    let p = params();
    let mut s = PvtStream::new();
    s.reset(0.01);
    let pts = vec![point(0.0, 0.0); MAX_BATCH];
    s.stage(1, &pts).unwrap();
    s.commit(1, &JointSample::default(), &p).unwrap();
    s.stage(1, &pts[..100]).unwrap();
    let e = s.commit(1, &JointSample::default(), &p).unwrap_err();
    assert_eq!(
        e,
        BatchError::QueueFull {
            offered: 100,
            free: DEFAULT_PVT_CAPACITY - MAX_BATCH
        }
    );
    assert_eq!(s.queued(), MAX_BATCH);
}

#[test]
fn a_batch_too_long_is_refused_whole() {
    let p = params();
    let mut s = PvtStream::new();
    s.reset(0.01);
    s.stage(1, &vec![point(0.0, 0.0); MAX_BATCH - 1]).unwrap();
    assert!(s.stage(1, &[point(0.0, 0.0); 2]).is_err());
    assert!(
        s.stage(1, &[point(0.0, 0.0); 1]).is_err(),
        "the rest is ignored"
    );
    let e = s.commit(1, &JointSample::default(), &p).unwrap_err();
    assert_eq!(e, BatchError::TooLong { limit: MAX_BATCH });
    assert_eq!(s.queued(), 0);
    // The next batch starts clean.
    s.stage(1, &[point(0.0, 0.0); 3]).unwrap();
    s.commit(1, &JointSample::default(), &p).unwrap();
    assert_eq!(s.queued(), 3);
}

#[test]
fn the_gateway_computes_the_same_point_limits_as_the_core() {
    let cfg = RobotConfig::prob2_default();
    let p = JointParams::from_config(&cfg);
    let l = PointLimits::from_config(&cfg);
    assert_eq!((l.reach_min, l.reach_max), (p.reach_min, p.reach_max));
    assert_eq!(l.velocity, core::array::from_fn(|i| p.limits[i].velocity));
}

#[test]
fn batches_of_two_clients_do_not_mix() {
    let p = params();
    let mut s = PvtStream::new();
    s.reset(0.01);
    s.stage(1, &[point(0.0, 0.0); 3]).unwrap();
    s.stage(2, &[point(0.0, 0.0); 2]).unwrap();
    s.commit(2, &JointSample::default(), &p).unwrap();
    assert_eq!(s.queued(), 2);
}
