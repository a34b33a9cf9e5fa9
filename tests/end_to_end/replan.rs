//! End to end (real launcher, simulated arm): `move_axis` and `move_all` sent while the arm
//! moves are re-planned from the commanded state (docs/protocol.md, "move_axis, move_all").
//!
//! Every status seen during a move is checked for continuity: in PVT the reported velocity is
//! the commanded one, and between two statuses it may change by at most the axis's maximum
//! acceleration times the controller's time between them (cycle numbers times the period: the
//! trajectory's own clock, not wall-clock, and not the drives' sample time, which moves with
//! each cycle's wake-up). The
//! arrival is checked against the simulation's ground truth (`sim` `true_position`), and the
//! mode stays PVT throughout (no safety trip).

use crate::common;

use common::{
    Client, Mcm, WAIT, assert_ok, assert_status, calibrated, max_abs, move_all, move_axis, six,
};
use mcm_shared::config::RobotConfig;
use serde_json::Value;
use std::time::{Duration, Instant};

/// Pause between polls (pacing only; every loop ends on an observed condition).
const POLL_PAUSE: Duration = Duration::from_millis(5);
/// The true arm within this of the target [deg] counts as arrived.
const ARRIVED: f64 = 0.05;
/// The status with its detail (the cycle number).
const DETAIL: &str = r#"{"command":"status","arguments":{"detail":true}}"#;

/// The controller's time of a detailed status [s]: its cycle number times the period.
fn cycle_time(s: &Value) -> f64 {
    let cycle = s["detail"]["cycle"].as_u64();
    let period = s["detail"]["timing"]["period_s"].as_f64();
    match (cycle, period) {
        (Some(k), Some(p)) => k as f64 * p,
        _ => panic!("no cycle or period in {s}"),
    }
}

/// Start, calibrate, enter PVT at rest.
fn in_pvt(tag: &str) -> (Mcm, Client) {
    let (mcm, mut c) = calibrated(tag);
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    (mcm, c)
}

/// Watches the statuses of a moving arm: PVT throughout, the commanded velocity continuous.
struct Watch {
    max_acceleration: [f64; 6],
    last: Option<(f64, [f64; 6])>,
    /// Largest velocity step seen, as a share of what the acceleration limit allows.
    worst: f64,
}

impl Watch {
    fn new() -> Watch {
        let cfg = RobotConfig::prob2_default();
        Watch {
            max_acceleration: std::array::from_fn(|i| cfg.axes[i].max_acceleration_deg_s2),
            last: None,
            worst: 0.0,
        }
    }

    /// Poll one status and check it against the previous one.
    fn poll(&mut self, c: &mut Client) -> Value {
        let s = c.request(DETAIL);
        assert_status(&s, "PVT");
        let t = cycle_time(&s);
        let v = six(&s["axis_states"]["velocity"]);
        if let Some((t0, v0)) = self.last {
            let dt = t - t0;
            assert!(dt >= 0.0, "robot time goes back: {t0} -> {t}");
            for i in 0..6 {
                // The reported velocity is rounded to 1e-6 deg/s.
                let allowed = self.max_acceleration[i] * dt + 1e-5;
                let step = (v[i] - v0[i]).abs();
                assert!(
                    step <= allowed,
                    "axis {}: commanded velocity jumps {v0:?} -> {v:?} in {dt} s",
                    i + 1
                );
                if dt > 0.0 {
                    self.worst = self.worst.max(step / allowed);
                }
            }
        }
        self.last = Some((t, v));
        s
    }

    /// Poll until the commanded motion ended and the true arm is within [`ARRIVED`] of
    /// `target` on the axes given (`None`: not checked); returns the robot time then.
    fn until_arrived(&mut self, c: &mut Client, target: &[Option<f64>; 6]) -> f64 {
        let deadline = Instant::now() + WAIT;
        loop {
            let s = self.poll(c);
            let truth = c.truth().0;
            let there = (0..6).all(|i| target[i].is_none_or(|q| (truth[i] - q).abs() < ARRIVED));
            if there && max_abs(&six(&s["axis_states"]["velocity"])) == 0.0 {
                return cycle_time(&s);
            }
            assert!(
                Instant::now() < deadline,
                "not arrived at {target:?}: true {truth:?}, last status {s}"
            );
            std::thread::sleep(POLL_PAUSE);
        }
    }

    /// Poll until the true position of axis `i` (0-based) passes `q` upward.
    fn until_past(&mut self, c: &mut Client, i: usize, q: f64) {
        let deadline = Instant::now() + WAIT;
        while c.truth().0[i] <= q {
            self.poll(c);
            assert!(Instant::now() < deadline, "axis {} never passed {q}", i + 1);
            std::thread::sleep(POLL_PAUSE);
        }
    }
}

#[test]
fn a_move_retargeted_mid_way_arrives_and_one_sent_as_the_last_arrives_is_accepted() {
    let (_mcm, mut c) = in_pvt("replan-retarget");
    let mut w = Watch::new();
    w.poll(&mut c);
    assert_ok(&c.request(&move_axis(1, 60.0, 0.8)));
    w.until_past(&mut c, 0, 20.0);
    // Behind the moving axis: it brakes, turns back and arrives.
    assert_ok(&c.request(&move_axis(1, -10.0, 0.5)));
    w.until_arrived(&mut c, &[Some(-10.0), Some(0.0), None, None, None, None]);

    // A move sent right as the previous one arrives (the true arm already within 0.05 deg,
    // the commanded motion not yet over) is accepted, not refused as busy.
    assert_ok(&c.request(&move_axis(1, 0.0, 0.5)));
    let deadline = Instant::now() + WAIT;
    loop {
        let s = w.poll(&mut c);
        let moving = max_abs(&six(&s["axis_states"]["velocity"])) > 0.0;
        if moving && (c.truth().0[0]).abs() < ARRIVED {
            break;
        }
        assert!(Instant::now() < deadline, "never caught the arrival: {s}");
    }
    assert_ok(&c.request(&move_axis(1, 3.0, 0.5)));
    w.until_arrived(&mut c, &[Some(3.0), None, None, None, None, None]);
    eprintln!("largest velocity step: {:.2} of the limit", w.worst);
}

#[test]
fn axes_run_independently_and_move_all_during_motion_answers_the_new_plan() {
    let (_mcm, mut c) = in_pvt("replan-axes");
    let mut w = Watch::new();
    w.poll(&mut c);
    assert_ok(&c.request(&move_axis(1, 40.0, 0.5)));
    w.until_past(&mut c, 0, 5.0);
    // Axis 2 starts while axis 1 moves; both arrive.
    assert_ok(&c.request(&move_axis(2, -20.0, 0.5)));
    w.until_arrived(&mut c, &[Some(40.0), Some(-20.0), None, None, None, None]);

    // move_all while axis 3 moves fast: the result is the new plan's.
    assert_ok(&c.request(&move_axis(3, 50.0, 1.0)));
    w.until_past(&mut c, 2, 10.0);
    let target = [0.0, 0.0, 0.0, 20.0, 0.0, 0.0];
    let before = w.poll(&mut c);
    let v3 = six(&before["axis_states"]["velocity"])[2];
    let r = c.request(&move_all(&target, 0.5));
    assert_eq!(r["result_type"], "move_all", "{r}");
    let t0 = cycle_time(&w.poll(&mut c));
    let duration = r["max_time_to_target"]
        .as_f64()
        .expect("max_time_to_target");
    let v = six(&r["velocities"]);
    // Axis 1 travels 40 deg at 45 deg/s, about 1.1 s; axis 3 is moving fast away from its
    // new target and must brake and come back: it is the longest, and its peak velocity is
    // at least the one it had.
    assert_eq!(r["longest"], 3, "{r}");
    assert!(v[2] >= v3.abs() - 0.5 && v[0] > 0.0 && v[4] == 0.0, "{r}");
    let arrived = w.until_arrived(&mut c, &target.map(Some));
    let took = arrived - t0;
    // The reply comes at most a cycle before the status that follows it; arrival is seen at
    // most one poll (a few cycles) late.
    assert!(
        took <= duration + 0.05 && took >= duration - 0.05,
        "arrived {took:.3} s after the reply, max_time_to_target {duration:.3} s"
    );
    eprintln!("largest velocity step: {:.2} of the limit", w.worst);
}
