//! End to end: the HMI's Cartesian words (`pose`, `tool`, `moveto`) against the running robot,
//! over telnet as `hmi::` speaks it. What `pose` shows is compared with the `status` of a JSON
//! connection (millimetres of its `cartesian_state`, roll/pitch/yaw of its quaternion);
//! `tool` with `detail.tool`; `moveto` on the simulation's ground truth through the MCM's own
//! kinematics with the tool that was set.

use crate::common;
use crate::hmi::Telnet;

use common::{Mcm, six};
use mcm_kinematics::{Kinematics, quaternion_from_rpy_deg, rpy_deg_from_quaternion};
use mcm_shared::config::RobotConfig;
use serde_json::Value;

const DETAIL: &str = r#"{"command":"status","arguments":{"detail":true}}"#;

/// The six numbers of the row after `pose`'s unit row (x y z mm, roll pitch yaw deg).
fn pose_row(out: &str) -> [f64; 6] {
    let mut lines = out
        .lines()
        .skip_while(|l| !l.contains("TCP in the base frame"));
    let row = lines
        .nth(3)
        .unwrap_or_else(|| panic!("no pose row:\n{out}"));
    let v: Vec<f64> = row
        .split_whitespace()
        .map(|w| {
            w.parse()
                .unwrap_or_else(|_| panic!("{w} in {row:?}:\n{out}"))
        })
        .collect();
    v.try_into()
        .unwrap_or_else(|_| panic!("six numbers: {row:?}"))
}

fn numbers<const N: usize>(v: &Value) -> [f64; N] {
    let a: Vec<f64> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    a.try_into().unwrap()
}

/// The largest difference of two angle triples [deg], a whole turn apart counting as none.
fn angle_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            let d = (x - y).rem_euclid(360.0);
            d.min(360.0 - d)
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_person_reads_the_pose_sets_the_tool_and_moves_to_a_pose_in_mm_and_degrees() {
    let mcm = Mcm::start("hmi-cartesian");
    let mut json = mcm.client();
    json.wait_drives_online();
    let mut t = Telnet::connect(mcm.hmi);
    t.expect("mcm OFF> ");
    let out = t.run("pose", b"\r\n", "OFF");
    assert!(
        out.contains("no TCP pose: not every axis is calibrated"),
        "{out}"
    );
    let out = t.run("calibrate", b"\r\n", "HOLD");
    assert!(!out.contains("ERROR"), "calibrate failed:\n{out}");

    // `pose`: the status's TCP in millimetres and degrees; the configuration's tool.
    let out = t.run("pose", b"\r\n", "HOLD");
    let shown = pose_row(&out);
    let s = json.request(DETAIL);
    let c = &s["cartesian_state"];
    let mm = numbers::<3>(&c["position"]).map(|x| x * 1000.0);
    let rpy = rpy_deg_from_quaternion(numbers::<4>(&c["orientation"]));
    assert!(
        (0..3).all(|i| (shown[i] - mm[i]).abs() < 0.006),
        "{shown:?} vs {mm:?} mm:\n{out}"
    );
    assert!(
        angle_diff(&shown[3..], &rpy) < 0.001,
        "{shown:?} vs {rpy:?}:\n{out}"
    );
    assert!(
        out.contains("load 3.800 kg, centre of mass at      0.00      0.00     80.00 mm"),
        "{out}"
    );

    // `tool`: the TCP typed in mm and degrees, the load kept.
    let out = t.run("tool 20 0 150 0 0 90", b"\r\n", "HOLD");
    assert!(
        out.contains("OK") && out.contains("roll pitch yaw     0.000     0.000    90.000 deg"),
        "{out}"
    );
    let tool = &json.request(DETAIL)["detail"]["tool"];
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert_eq!(
        numbers::<3>(&tool["tcp"]["position"]),
        [0.02, 0.0, 0.15],
        "{tool}"
    );
    let o = numbers::<4>(&tool["tcp"]["orientation"]);
    assert!(
        (0..4).all(|i| (o[i] - [0.0, 0.0, h, h][i]).abs() < 1e-6),
        "{tool}"
    );
    assert_eq!(tool["mass"], 3.8, "the load is kept: {tool}");
    let out = t.run("tool 0 0 150 0 0 0 mass=9", b"\r\n", "HOLD");
    assert!(out.contains("nothing was sent"), "{out}");

    // `moveto`: the true TCP (the tool just set) arrives at the pose typed.
    let mut kin = Kinematics::from_config(&RobotConfig::prob2_default()).unwrap();
    kin.set_tcp(mcm_kinematics::isometry(
        [0.02, 0.0, 0.15],
        [0.0, 0.0, h, h],
    ))
    .unwrap();
    let tcp = |q: &[f64; 6]| kin.tcp_pose(&q.map(f64::to_radians));
    let goal = tcp(&[-25.0, 15.0, 75.0, 30.0, -45.0, 60.0]);
    let p = goal.translation.vector * 1000.0;
    let r = goal.rotation.coords;
    let goal_rpy = rpy_deg_from_quaternion([r.x, r.y, r.z, r.w]);
    let line = format!(
        "moveto {:.4} {:.4} {:.4} {:.4} {:.4} {:.4} vf=1",
        p.x, p.y, p.z, goal_rpy[0], goal_rpy[1], goal_rpy[2]
    );
    t.run("pvt", b"\r\n", "PVT");
    let out = t.run(&line, b"\r\n", "PVT");
    assert!(
        out.contains("OK - every axis arrives within"),
        "{line}:\n{out}"
    );
    let typed = quaternion_from_rpy_deg(goal_rpy);
    json.wait_truth("the true TCP at the pose typed, at rest", |q, v| {
        let now = tcp(q);
        (now.translation.vector - goal.translation.vector).norm() < 1e-3
            && v.iter().all(|x| x.abs() < 0.1)
    });
    let (q, _) = json.truth();
    let r = tcp(&q).rotation.coords;
    let turned = common::orientation_angle(&[r.x, r.y, r.z, r.w], &typed).to_degrees();
    assert!(turned < 0.1, "{turned} deg from the orientation typed");
    // And `pose` says so, in the words it was typed in.
    json.wait_status("the commanded move ended", |s| {
        six(&s["axis_states"]["velocity"]).iter().all(|v| *v == 0.0)
    });
    let shown = pose_row(&t.run("pose", b"\r\n", "PVT"));
    assert!(
        (0..3).all(|i| (shown[i] - [p.x, p.y, p.z][i]).abs() < 0.02)
            && angle_diff(&shown[3..], &goal_rpy) < 0.01,
        "{shown:?} vs {p:?} {goal_rpy:?}"
    );
}
