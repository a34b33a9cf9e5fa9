//! End to end (real launcher, simulated arm): `inverse_kinematics` and `move_to_pose`
//! (`docs/protocol.md`, `docs/cartesian.md`). The poses are computed here with the MCM's own
//! kinematics (`mcm-kinematics`, the TCP on the flange as configured) from joint positions; the
//! arrival is checked on the simulation's ground truth (`sim` `true_position`) through the
//! forward kinematics, after the planned duration has passed on the robot's clock.

use crate::common;

use common::tcp::{START, kinematics, minus, norm, true_tcp};
use common::{Client, Mcm, WAIT, assert_status, calibrated, max_diff, move_all, six, time_of};
use mcm_kinematics::Kinematics;
use serde_json::{Value, json};
use std::time::{Duration, Instant};

/// The configuration whose TCP pose `move_to_pose` is sent to [deg].
const GOAL: [f64; 6] = [-25.0, 15.0, 75.0, 30.0, -45.0, 60.0];
/// How far the true TCP may end from the pose [m].
const ARRIVED_M: f64 = 1e-3;
/// How far a solution's pose may be from the pose asked [m].
const SOLUTION_M: f64 = 1e-6;
/// A true axis velocity below this counts as still [deg/s] (the simulated arm at rest
/// jitters by a few hundredths).
const STILL_DEG_S: f64 = 0.1;
/// How far a true axis may wander while the arm holds still [deg].
const HELD_DEG: f64 = 0.01;
/// The status with its detail (the commanded position).
const DETAIL: &str = r#"{"command":"status","arguments":{"detail":true}}"#;

/// The TCP pose of `q_deg`: position [m] and unit quaternion [x, y, z, w].
fn pose(kin: &Kinematics, q_deg: &[f64; 6]) -> ([f64; 3], [f64; 4]) {
    let t = true_tcp(kin, q_deg, &[0.0; 6]);
    (t.position, t.orientation)
}

/// The distance between two positions [m].
fn distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    norm(&minus(a, b))
}

/// The angle between two orientations [deg].
fn angle_deg(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    common::orientation_angle(a, b).to_degrees()
}

fn command(name: &str, position: &[f64; 3], orientation: &[f64; 4]) -> String {
    json!({"command": name, "arguments": {"position": position, "orientation": orientation}})
        .to_string()
}

/// Assert an ERROR answering `command` with `code` and `outcome`.
fn assert_refused(v: &Value, command: &str, code: &str, outcome: &str) {
    assert!(common::is_error(v), "expected an ERROR, got {v}");
    assert_eq!(v["error_code"], code, "{v}");
    assert_eq!(v["command"], command, "{v}");
    assert_eq!(v["outcome"], outcome, "{v}");
}

/// Wait until the robot's clock has passed `until` [s] and the true arm has stopped; its true
/// position.
fn settled_after(c: &mut Client, until: f64) -> [f64; 6] {
    let deadline = Instant::now() + WAIT;
    loop {
        let s = c.request(DETAIL);
        let (p, v) = c.truth();
        if time_of(&s) >= until && v.iter().all(|x| x.abs() < STILL_DEG_S) {
            return p;
        }
        assert!(
            Instant::now() < deadline,
            "timed out waiting for the move to end at {until} s; last status {s}"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// A joint move to `target` from PVT, to its end on the robot's clock.
fn move_to(c: &mut Client, target: &[f64; 6]) -> [f64; 6] {
    let r = c.request(&move_all(target, 1.0));
    assert_eq!(r["result_type"], "move_all", "{r}");
    let start = time_of(&c.request(DETAIL));
    let duration = r["max_time_to_target"].as_f64().unwrap();
    settled_after(c, start + duration)
}

/// Start calibrated, in PVT at [`START`].
fn at_start(tag: &str) -> (Mcm, Client) {
    let (mcm, mut c) = calibrated(tag);
    assert_status(&c.request(common::PVT_ANY_RATE), "PVT");
    let p = move_to(&mut c, &START);
    assert!(max_diff(&p, &START) < 0.05, "{p:?}");
    (mcm, c)
}

#[test]
fn inverse_kinematics_of_the_present_pose_gives_the_present_position_first() {
    let kin = kinematics();
    let (_mcm, mut c) = at_start("ik-present");
    let present = six(&c.request(DETAIL)["axis_states"]["position"]);
    let (position, orientation) = pose(&kin, &present);
    let r = c.request(&command("inverse_kinematics", &position, &orientation));
    assert_eq!(r["result_type"], "inverse_kinematics", "{r}");
    let solutions: Vec<[f64; 6]> = r["solutions"]
        .as_array()
        .unwrap_or_else(|| panic!("no solutions: {r}"))
        .iter()
        .map(six)
        .collect();
    assert!(solutions.len() > 1, "{r}");
    // The seed is the present position of the newest state: the arm holds still.
    assert!(max_diff(&solutions[0], &present) < 1e-3, "{r}");
    for q in &solutions {
        let (p, o) = pose(&kin, q);
        assert!(distance(&p, &position) < SOLUTION_M, "{q:?}: {p:?} {r}");
        assert!(angle_deg(&o, &orientation) < 1e-4, "{q:?}: {o:?} {r}");
    }
    // With a seed: the solution nearest it first.
    let second = solutions[1];
    let with_seed = json!({"command": "inverse_kinematics", "arguments": {
        "position": position, "orientation": orientation, "seed": second}});
    let r = c.request(&with_seed.to_string());
    assert!(max_diff(&six(&r["solutions"][0]), &second) < 1e-3, "{r}");
}

#[test]
fn an_unreachable_pose_is_refused_and_nothing_moves() {
    let (_mcm, mut c) = at_start("ik-unreachable");
    let far = [3.0, 0.0, 0.5];
    let upright = [0.0, 0.0, 0.0, 1.0];
    let r = c.request(&command("inverse_kinematics", &far, &upright));
    assert_refused(&r, "inverse_kinematics", "unreachable", "refused");
    assert!(
        r["error_message"]
            .as_str()
            .unwrap()
            .contains("the wrist centre would be"),
        "{r}"
    );
    let before = six(&c.request(DETAIL)["detail"]["commanded_position"]);
    let (true_before, _) = c.truth();
    let r = c.request(&command("move_to_pose", &far, &upright));
    assert_refused(&r, "move_to_pose", "unreachable", "refused");
    // Nothing was sent: the plan is unchanged, and the arm still holds where it was.
    let s = c.request(DETAIL);
    assert_status(&s, "PVT");
    assert_eq!(six(&s["detail"]["commanded_position"]), before, "{s}");
    let (true_after, _) = c.truth();
    assert!(
        max_diff(&true_before, &true_after) < HELD_DEG,
        "the arm moved: {true_before:?} -> {true_after:?}"
    );
}

#[test]
fn move_to_pose_brings_the_tcp_there() {
    let kin = kinematics();
    let (mcm, mut c) = at_start("move-to-pose");
    let (position, orientation) = pose(&kin, &GOAL);

    // Another client does not control the arm: the core's refusal.
    let mut other = mcm.client();
    let r = other.request(&command("move_to_pose", &position, &orientation));
    assert_refused(&r, "move_to_pose", "not_owner", "refused");
    // Control is checked first, as the core checks it: even for a pose out of reach.
    let r = other.request(&command(
        "move_to_pose",
        &[3.0, 0.0, 0.5],
        &[0.0, 0.0, 0.0, 1.0],
    ));
    assert_refused(&r, "move_to_pose", "not_owner", "refused");

    // The solution nearest the present position, which the joint move goes to.
    let present = six(&c.request(DETAIL)["axis_states"]["position"]);
    let goal = kin.tcp_pose(&GOAL.map(f64::to_radians));
    let solutions = kin.inverse(&goal, &present.map(f64::to_radians)).unwrap();
    let nearest = solutions[0].q.map(f64::to_degrees);
    let line = json!({"command": "move_to_pose", "arguments": {
        "position": position, "orientation": orientation, "velocity_factor": 1.0}});
    let r = c.request(&line.to_string());
    assert_eq!(r["result_type"], "move_all", "{r}");
    let start = time_of(&c.request(DETAIL));
    let duration = r["max_time_to_target"].as_f64().unwrap();
    assert!(duration > 0.1, "{r}");
    let truth = settled_after(&mut c, start + duration);
    let (p, o) = pose(&kin, &truth);
    assert!(
        distance(&p, &position) < ARRIVED_M,
        "the true TCP ends at {p:?}, {} m from {position:?}",
        distance(&p, &position)
    );
    assert!(
        angle_deg(&o, &orientation) < 0.1,
        "{o:?} vs {orientation:?}"
    );
    assert!(
        max_diff(&truth, &nearest) < 0.05,
        "the arm ends at {truth:?}, not at the nearest solution {nearest:?}"
    );

    // Outside PVT: the core's refusal of the joint move.
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    let (position, orientation) = pose(&kin, &START);
    let r = c.request(&command("move_to_pose", &position, &orientation));
    assert_refused(&r, "move_to_pose", "wrong_mode", "refused");
}
