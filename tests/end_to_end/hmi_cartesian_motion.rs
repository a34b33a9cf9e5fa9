//! End to end: the HMI moving the TCP, over telnet as `hmi::` speaks it: `movel` (a straight
//! line typed in mm, roll/pitch/yaw deg and mm/s) and the jog screen's Cartesian jog (`jog x`,
//! the keys choosing the direction and the frame). Followed on the simulation's ground truth
//! (`sim` `true_position` through the MCM's own kinematics, the configured TCP); every wait
//! bounded.

use crate::common;
use crate::hmi::Telnet;

use common::tcp::{self, START, TrueTcp, kinematics, minus, norm};
use common::{Client, assert_ok, assert_status, calibrated, max_diff};
use mcm_kinematics::{Kinematics, rpy_deg_from_quaternion};
use std::time::Duration;

const STATUS: &str = r#"{"command":"status"}"#;

fn true_tcp(c: &mut Client, kin: &Kinematics) -> TrueTcp {
    let (p, v) = c.truth();
    tcp::true_tcp(kin, &p, &v)
}

/// The calibrated arm at [`START`] in PVT, moved there by the HMI session, which keeps the
/// control; `c` reads the truth.
fn at_start(tag: &str) -> (common::Mcm, Client, Telnet) {
    let (mcm, mut c) = calibrated(tag);
    assert_ok(&c.request(r#"{"command":"release_control"}"#));
    let mut t = Telnet::connect(mcm.hmi);
    t.expect("mcm HOLD> ");
    t.run("pvt", b"\r\n", "PVT");
    let line = format!("move_all {} vf=1", START.map(|x| x.to_string()).join(" "));
    let out = t.run(&line, b"\r\n", "PVT");
    assert!(out.contains("OK"), "{line}:\n{out}");
    c.wait_truth("at the start", |p, v| {
        max_diff(p, &START) < 0.05 && v.iter().all(|x| x.abs() < 0.1)
    });
    (mcm, c, t)
}

/// The TCP at rest (every axis slower than 0.05 deg/s).
fn at_rest(c: &mut Client, kin: &Kinematics, what: &str) -> TrueTcp {
    let (p, v) = c.wait_truth(what, |_, v| v.iter().all(|x| x.abs() < 0.05));
    tcp::true_tcp(kin, &p, &v)
}

/// The line typing `position` [m] (and the orientation's roll, pitch, yaw) in mm and degrees.
fn movel(position: [f64; 3], orientation: Option<[f64; 4]>, speed_mm_s: f64) -> String {
    let mm = position.map(|x| format!("{:.4}", x * 1000.0)).join(" ");
    let rpy = orientation.map_or(String::new(), |o| {
        let r = rpy_deg_from_quaternion(o);
        format!(" {:.6} {:.6} {:.6}", r[0], r[1], r[2])
    });
    format!("movel {mm}{rpy} v={speed_mm_s}")
}

#[test]
fn movel_brings_the_true_tcp_along_a_line_typed_in_millimetres_and_degrees() {
    let kin = kinematics();
    let (_mcm, mut c, mut t) = at_start("hmi-movel");
    let start = true_tcp(&mut c, &kin);

    // 10 cm along the base's x, the orientation typed as it is.
    let goal = [
        start.position[0] + 0.1,
        start.position[1],
        start.position[2],
    ];
    let line = movel(goal, Some(start.orientation), 100.0);
    let out = t.run(&line, b"\r\n", "PVT");
    assert!(
        out.contains("OK - the TCP arrives in") && out.contains("the axes there [deg]"),
        "{line}:\n{out}"
    );
    let mut worst: f64 = 0.0;
    let deadline = std::time::Instant::now() + common::WAIT;
    let end = loop {
        assert!(
            std::time::Instant::now() < deadline,
            "the true TCP not at {goal:?} and at rest within {:?}",
            common::WAIT
        );
        let (q, v) = c.truth();
        let now = tcp::true_tcp(&kin, &q, &v);
        // Off the line from the start to the goal: only x changes.
        worst = worst.max(norm(&minus(
            &[start.position[0], now.position[1], now.position[2]],
            &start.position,
        )));
        if norm(&minus(&now.position, &goal)) < 1e-3 && v.iter().all(|x| x.abs() < 0.05) {
            break now;
        }
        assert!(now.position[0] < goal[0] + 1e-3, "beyond the goal: {now:?}");
        std::thread::sleep(Duration::from_millis(10));
        assert_status(&c.request(STATUS), "PVT");
    };
    assert!(worst < 1e-3, "{worst} m off the line");
    let turned = common::orientation_angle(&start.orientation, &end.orientation).to_degrees();
    assert!(turned < 0.1, "turned {turned} deg");

    // Without roll, pitch and yaw: 10 cm down, the orientation kept.
    let goal = [end.position[0], end.position[1], end.position[2] - 0.1];
    let line = movel(goal, None, 200.0);
    let out = t.run(&line, b"\r\n", "PVT");
    assert!(out.contains("OK - the TCP arrives in"), "{line}:\n{out}");
    c.wait_truth("the true TCP 10 cm lower, at rest", |q, v| {
        let now = tcp::true_tcp(&kin, q, v);
        norm(&minus(&now.position, &goal)) < 1e-3 && v.iter().all(|x| x.abs() < 0.05)
    });
    let lower = true_tcp(&mut c, &kin);
    let turned = common::orientation_angle(&start.orientation, &lower.orientation).to_degrees();
    assert!(
        turned < 0.1,
        "turned {turned} deg without an orientation typed"
    );

    // Refusals name what was wrong; nothing moves.
    let (before, _) = c.truth();
    // Beyond the reach: the planner refuses the path where it first fails (an axis's range
    // on the way out, or the reach), with its error code.
    let out = t.run("movel 3000 0 500", b"\r\n", "PVT");
    assert!(
        (out.contains("error [out_of_range]") || out.contains("error [unreachable]"))
            && out.contains("move_linear refused")
            && out.contains("nothing moved"),
        "{out}"
    );
    let out = t.run("movel 400 0 500 v=2000", b"\r\n", "PVT");
    assert!(
        out.contains("speed = 2000 mm/s is not allowed; expected a number from 1 to 1000 mm/s"),
        "{out}"
    );
    let out = t.run("movel 400 0", b"\r\n", "PVT");
    assert!(
        out.contains("needs 3 numbers X Y Z or 6 X Y Z ROLL PITCH YAW, got 2"),
        "{out}"
    );
    let (after, v) = c.truth();
    assert!(
        max_diff(&before, &after) < 1e-3 && v.iter().all(|x| x.abs() < 0.05),
        "moved: {before:?} -> {after:?}"
    );
}

/// Hold `key` down as a terminal's auto-repeat sends it: `n` times, every 30 ms.
fn hold_key(t: &mut Telnet, key: &[u8], n: usize) {
    for _ in 0..n {
        t.send(key);
        std::thread::sleep(Duration::from_millis(30));
    }
}

#[test]
fn the_jog_screen_jogs_the_tcp_along_an_axis_of_the_base_or_the_tool_frame() {
    // A key every 30 ms of this test's clock keeps the jog going: timing, so alone.
    let _alone = crate::common::machine::alone();
    let kin = kinematics();
    let (_mcm, mut c, mut t) = at_start("hmi-cartesian-jog");
    t.run("hold", b"\r\n", "HOLD");
    t.send(b"jog x 30\r\n");
    t.expect("jogging the TCP x in the base frame at 30 mm/s");
    t.expect("jog TCP along X  base frame");
    assert_status(&c.request(STATUS), "VELOCITY_CONTROL");

    // `+` held for about a second: along the base's +x at 30 mm/s; let go, it stops.
    let start = true_tcp(&mut c, &kin);
    hold_key(&mut t, b"+", 33);
    let moving = true_tcp(&mut c, &kin);
    assert!(
        (norm(&moving.velocity) - 0.03).abs() < 0.0015 && moving.velocity[0] > 0.029,
        "at 30 mm/s along x: {:?}",
        moving.velocity
    );
    let end = at_rest(&mut c, &kin, "stopped after the key was let go");
    let d = minus(&end.position, &start.position);
    assert!(
        d[0] > 0.025 && d[1].abs() < 0.003 && d[2].abs() < 0.003,
        "along the base's x: {d:?}"
    );
    assert_status(&c.request(STATUS), "VELOCITY_CONTROL");

    // `f` switches to the tool frame, `z` chooses its z axis; `-` held moves against it.
    t.send(b"f");
    t.expect("jog TCP along X  tool frame");
    t.send(b"z");
    t.expect("jog TCP along Z  tool frame");
    let start = end;
    hold_key(&mut t, b"-", 33);
    let end = at_rest(&mut c, &kin, "stopped after `-` was let go");
    let d = minus(&end.position, &start.position);
    let along: f64 = (0..3).map(|i| -d[i] * start.z[i]).sum();
    let across = norm(&core::array::from_fn(|i| d[i] + along * start.z[i]));
    assert!(
        along > 0.025 && across < 0.003,
        "against the TCP's z {:?}: {d:?} ({along} along, {across} across)",
        start.z
    );
    let turned = common::orientation_angle(&start.orientation, &end.orientation).to_degrees();
    assert!(turned < 0.5, "turned {turned} deg moving along");

    // `Z`: about the TCP's z at 10 deg/s (the default); the TCP stays where it is.
    t.send(b"Z");
    t.expect("jog TCP about Z tool frame");
    let start = end;
    hold_key(&mut t, b"\x1b[A", 33);
    let end = at_rest(&mut c, &kin, "stopped after Up was let go");
    let turned = common::orientation_angle(&start.orientation, &end.orientation).to_degrees();
    let moved = norm(&minus(&end.position, &start.position));
    assert!(
        turned > 8.0 && turned < 14.0 && moved < 0.002,
        "turned {turned} deg, moved {moved} m"
    );
    // The TCP's z axis is where it was: the turn was about it.
    let tilt = norm(&minus(&end.z, &start.z));
    assert!(tilt < 0.01, "its z moved by {tilt}");

    // One press and no repeats (a key tapped): the jog moves for the first repeat's delay
    // (0.7 s, about 21 mm at 30 mm/s), then stops by itself, the mode kept.
    t.send(b"x");
    t.expect("jog TCP along X  tool frame");
    let start = end;
    t.send(b"+");
    c.wait_truth("the tap moving the arm", |_, v| {
        v.iter().any(|x| x.abs() > 0.5)
    });
    let end = at_rest(&mut c, &kin, "stopped after the tap");
    let moved = norm(&minus(&end.position, &start.position));
    assert!(
        (0.01..0.03).contains(&moved),
        "a tap moved the TCP {moved} m"
    );
    assert_status(&c.request(STATUS), "VELOCITY_CONTROL");

    // `q` stops with `hold`.
    t.send(b"q");
    t.expect("jog ended; mode HOLD");
    t.expect("mcm HOLD> ");
    assert_status(&c.request(STATUS), "HOLD");

    // A jog speed beyond set_cartesian_velocity's range is refused before anything is sent.
    let out = t.run("jog y 1500", b"\r\n", "HOLD");
    assert!(
        out.contains("speed = 1500 is not allowed") && out.contains("at most 1000 mm/s"),
        "{out}"
    );
}
