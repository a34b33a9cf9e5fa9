//! End to end (real launcher, simulated arm): `move_linear` (`docs/protocol.md`,
//! `docs/cartesian.md`). The true TCP is the simulation's ground truth (`sim`
//! `true_position`, `true_velocity`) through the MCM's own kinematics (the TCP on the flange
//! as configured), sampled all through the move; the move's end is found on the robot's
//! clock.

use crate::common;

use common::tcp::{START, kinematics, minus, norm, true_tcp};
use common::{Client, Mcm, WAIT, assert_status, calibrated, max_diff, move_all, six, time_of};
use serde_json::{Value, json};
use std::time::{Duration, Instant};

/// The line's length [m] and the TCP's requested speed [m/s].
const LENGTH_M: f64 = 0.15;
const SPEED_M_S: f64 = 0.25;
/// How far the true TCP may leave the line [m], and end from the target [m] and [deg].
const ON_LINE_M: f64 = 1e-3;
const ARRIVED_M: f64 = 0.5e-3;
const ARRIVED_DEG: f64 = 0.1;
/// How much faster than requested the true TCP may move.
const SPEED_MARGIN: f64 = 1.05;
/// A true axis velocity below this counts as still [deg/s].
const STILL_DEG_S: f64 = 0.1;
/// How far a true axis may wander while the arm holds still, settling [deg].
const HELD_DEG: f64 = 0.05;
const DETAIL: &str = r#"{"command":"status","arguments":{"detail":true}}"#;

/// The distance of `p` from the segment `a`-`b` [m].
fn off_line(p: &[f64; 3], a: &[f64; 3], b: &[f64; 3]) -> f64 {
    let (d, pa) = (minus(b, a), minus(p, a));
    let along = (0..3).map(|i| pa[i] * d[i]).sum::<f64>() / norm(&d).powi(2);
    let s = along.clamp(0.0, 1.0);
    norm(&core::array::from_fn(|i| pa[i] - s * d[i]))
}

fn move_linear(position: &[f64; 3], velocity: f64) -> String {
    json!({"command": "move_linear", "arguments": {"position": position, "velocity": velocity}})
        .to_string()
}

/// Start calibrated, in PVT, at rest at [`START`].
fn at_start(tag: &str) -> (Mcm, Client) {
    let (mcm, mut c) = calibrated(tag);
    assert_status(&c.request(common::PVT_ANY_RATE), "PVT");
    let r = c.request(&move_all(&START, 1.0));
    assert_eq!(r["result_type"], "move_all", "{r}");
    let (p, _) = c.wait_truth("at START", |p, v| {
        max_diff(p, &START) < 0.05 && v.iter().all(|x| x.abs() < STILL_DEG_S)
    });
    assert!(max_diff(&p, &START) < 0.05, "{p:?}");
    (mcm, c)
}

#[test]
fn a_15_cm_line_keeps_the_true_tcp_on_it_and_within_the_speed() {
    let kin = kinematics();
    let (_mcm, mut c) = at_start("move-linear");
    let (q0, v0) = c.truth();
    let from = true_tcp(&kin, &q0, &v0);
    let a = from.position;
    // Sideways and down, 15 cm.
    let dir = [0.0, 2.0 / 5f64.sqrt(), -1.0 / 5f64.sqrt()];
    let b: [f64; 3] = core::array::from_fn(|i| a[i] + dir[i] * LENGTH_M);
    let r = c.request(&move_linear(&b, SPEED_M_S));
    assert_eq!(r["result_type"], "move_linear", "{r}");
    let duration = r["duration"].as_f64().unwrap();
    assert!(duration >= LENGTH_M / SPEED_M_S, "{r}");
    let ends = time_of(&c.request(DETAIL)) + duration;
    // Sample the true TCP all through the move, until the robot's clock has passed its end
    // and the arm is still.
    let (mut worst_off, mut fastest, mut samples) = (0.0f64, 0.0f64, 0);
    let deadline = Instant::now() + WAIT;
    let last = loop {
        let (q, v) = c.truth();
        let now = true_tcp(&kin, &q, &v);
        worst_off = worst_off.max(off_line(&now.position, &a, &b));
        fastest = fastest.max(norm(&now.velocity));
        samples += 1;
        let t = time_of(&c.request(DETAIL));
        if t >= ends && v.iter().all(|x| x.abs() < STILL_DEG_S) {
            break now;
        }
        assert!(
            Instant::now() < deadline,
            "the line did not end by {ends} s"
        );
    };
    assert!(
        samples >= 20,
        "only {samples} samples of a {duration} s move"
    );
    assert!(
        worst_off < ON_LINE_M,
        "the true TCP left the line by {worst_off} m"
    );
    assert!(
        fastest <= SPEED_M_S * SPEED_MARGIN,
        "the true TCP moved at {fastest} m/s, requested {SPEED_M_S}"
    );
    assert!(
        fastest > 0.8 * SPEED_M_S,
        "the line never came near its speed: {fastest} m/s"
    );
    let missed = norm(&minus(&last.position, &b));
    assert!(missed < ARRIVED_M, "ended {missed} m from the target");
    let turned = common::orientation_angle(&last.orientation, &from.orientation).to_degrees();
    assert!(
        turned < ARRIVED_DEG,
        "the orientation turned by {turned} deg"
    );
    // The joint target of the answer is where the arm is.
    let target = six(&r["joint_target"]);
    let (q, _) = c.truth();
    assert!(max_diff(&q, &target) < 0.05, "{q:?} vs {target:?}");
}

#[test]
fn an_unreachable_line_is_refused_and_the_arm_does_not_move() {
    let kin = kinematics();
    let (_mcm, mut c) = at_start("line-unreachable");
    let (before, v) = c.truth();
    let here = true_tcp(&kin, &before, &v).position;
    // 1.5 m straight up: beyond the reach part of the way.
    let up = [here[0], here[1], here[2] + 1.5];
    let r: Value = c.request(&move_linear(&up, 0.25));
    assert!(common::is_error(&r), "{r}");
    assert_eq!(r["error_code"], "unreachable", "{r}");
    assert_eq!(r["command"], "move_linear", "{r}");
    let words = r["error_message"].as_str().unwrap_or_default();
    assert!(words.contains("% of the path"), "{r}");
    // Nothing is commanded (the reported position in PVT is the commanded one), and the true
    // arm stays where it was.
    let s = c.request(DETAIL);
    let (t0, commanded) = (time_of(&s), six(&s["axis_states"]["position"]));
    loop {
        let (q, _) = c.truth();
        assert!(
            max_diff(&q, &before) < HELD_DEG,
            "the arm moved: {q:?} from {before:?}"
        );
        let s = c.request(DETAIL);
        assert_eq!(six(&s["axis_states"]["position"]), commanded, "{s}");
        if time_of(&s) > t0 + 0.3 {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_status(&c.request(DETAIL), "PVT");
}
