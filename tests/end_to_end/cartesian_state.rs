//! End to end (real launcher, simulated arm): `status` over JSON/TCP carries `cartesian_state`
//! once every axis is calibrated and not before, and it is the forward kinematics (and, for
//! its velocity, the Jacobian) of the axis values the same result reports, computed here with
//! `mcm-kinematics` from the configuration the MCM runs (docs/cartesian.md, docs/protocol.md).
//! The results' figures are rounded to 6 decimals: the tolerances allow for that.

use crate::common;

use common::{assert_ok, assert_status, max_abs, move_all, orientation_angle, six};
use mcm_kinematics::Kinematics;
use mcm_shared::config::RobotConfig;
use serde_json::Value;

/// Position [m] and linear velocity [m/s]: the rounding of the reported figures (5e-7) and of
/// the axis angles the kinematics start from.
const LINEAR: f64 = 2e-6;
/// Orientation [rad] (each quaternion component rounded) and angular velocity [deg/s].
const ANGULAR: f64 = 1e-5;

fn numbers<const N: usize>(v: &Value) -> [f64; N] {
    let a = v
        .as_array()
        .unwrap_or_else(|| panic!("expected {N} numbers, got {v}"));
    assert_eq!(a.len(), N, "expected {N} numbers, got {v}");
    std::array::from_fn(|i| a[i].as_f64().unwrap_or_else(|| panic!("not a number: {v}")))
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// Check `status`'s `cartesian_state` against the kinematics of its own `axis_states`; returns
/// the TCP's position [m] and linear velocity [m/s].
fn check_against_kinematics(kin: &Kinematics, status: &Value) -> ([f64; 3], [f64; 3]) {
    let c = &status["cartesian_state"];
    assert!(c.is_object(), "no cartesian_state: {status}");
    let q = six(&status["axis_states"]["position"]).map(f64::to_radians);
    let qd = six(&status["axis_states"]["velocity"]).map(f64::to_radians);
    let pose = kin.tcp_pose(&q);
    let j = kin.tcp_jacobian(&q);
    let twist: [f64; 6] = std::array::from_fn(|r| (0..6).map(|k| j[(r, k)] * qd[k]).sum());

    let position: [f64; 3] = numbers(&c["position"]);
    let t = pose.translation.vector;
    let off = distance(&position, &[t.x, t.y, t.z]);
    assert!(off < LINEAR, "position {off:e} m off: {status}");

    // [x, y, z, w], compared up to the sign (q and -q are one rotation).
    let o: [f64; 4] = numbers(&c["orientation"]);
    let e = pose.rotation.quaternion().coords;
    let angle = orientation_angle(&o, &[e.x, e.y, e.z, e.w]);
    assert!(angle < ANGULAR, "orientation {angle:e} rad off: {status}");
    assert!(o[3] >= 0.0, "w >= 0: {status}");

    let linear: [f64; 3] = numbers(&c["linear_velocity"]);
    let off = distance(&linear, &twist[..3]);
    assert!(off < LINEAR, "linear velocity {off:e} m/s off: {status}");
    let angular: [f64; 3] = numbers(&c["angular_velocity"]);
    let off = distance(
        &angular,
        &twist[3..]
            .iter()
            .map(|w| w.to_degrees())
            .collect::<Vec<_>>(),
    );
    assert!(
        off < ANGULAR,
        "angular velocity {off:e} deg/s off: {status}"
    );
    (position, linear)
}

#[test]
fn status_carries_the_tcp_of_its_own_axis_values_once_calibrated() {
    let kin = Kinematics::from_config(&RobotConfig::prob2_default()).unwrap();
    let mcm = common::Mcm::start("cartesian-state");
    let mut c = mcm.client();
    let before = c.wait_drives_online();
    assert!(
        before.get("cartesian_state").is_none(),
        "not calibrated: no cartesian_state: {before}"
    );
    assert_ok(&c.request(r#"{"command":"calibrate"}"#));

    // At zero after the calibration: the P-Rob2 upright, its TCP on the flange.
    let s = c.request(r#"{"command":"status"}"#);
    assert_status(&s, "HOLD");
    let (position, _) = check_against_kinematics(&kin, &s);
    assert!(
        distance(&position, &[0.0, 0.0, 1.035]) < 1e-3,
        "upright: {s}"
    );

    // Moving in PVT: the reported (commanded) axis values and the TCP's velocity from them.
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    let target = [30.0, -30.0, 40.0, 20.0, -40.0, 60.0];
    assert_eq!(
        c.request(&move_all(&target, 0.5))["result_type"],
        "move_all"
    );
    let moving = c.wait_status("the arm moving", |s| {
        max_abs(&six(&s["axis_states"]["velocity"])) > 10.0
    });
    let (_, linear) = check_against_kinematics(&kin, &moving);
    assert!(
        distance(&linear, &[0.0; 3]) > 0.01,
        "the TCP moves: {moving}"
    );
    // A few more while it moves, each against its own axis values.
    for _ in 0..5 {
        let s = c.request(r#"{"command":"status"}"#);
        check_against_kinematics(&kin, &s);
    }
}

/// `set_tool` moves the TCP: from the next cycle the core's `cartesian_state` is the TCP of
/// the new tool, and the gateway's `inverse_kinematics` solves for it (the present pose with
/// that TCP gives back the present position first).
#[test]
fn the_tcp_follows_set_tool_in_the_state_and_in_inverse_kinematics() {
    let tcp_position = [0.02, 0.0, 0.15];
    // 90 degrees about the flange's z axis.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let tcp_orientation = [0.0, 0.0, h, h];
    let mut kin = Kinematics::from_config(&RobotConfig::prob2_default()).unwrap();
    kin.set_tcp(mcm_kinematics::tcp_transform(&mcm_shared::tool::Tcp {
        position: tcp_position,
        orientation: tcp_orientation,
    }))
    .unwrap();

    let mcm = common::Mcm::start("cartesian-tool");
    let mut c = mcm.client();
    c.wait_drives_online();
    assert_ok(&c.request(r#"{"command":"calibrate"}"#));
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    let target = [20.0, -20.0, 50.0, 10.0, -30.0, 40.0];
    assert_eq!(
        c.request(&move_all(&target, 1.0))["result_type"],
        "move_all"
    );
    c.wait_status("the arm at the target", |s| {
        distance(&six(&s["axis_states"]["position"]), &target) < 1e-6
            && max_abs(&six(&s["axis_states"]["velocity"])) == 0.0
    });

    let set = serde_json::json!({"command": "set_tool", "arguments": {
        "tcp": {"position": tcp_position, "orientation": tcp_orientation},
        "mass": 3.8, "center_of_mass": [0.0, 0.0, 0.08]}});
    assert_ok(&c.request(&set.to_string()));
    let s = c.request(r#"{"command":"status","arguments":{"detail":true}}"#);
    assert_eq!(
        s["detail"]["tool"]["tcp"]["position"],
        serde_json::json!(tcp_position),
        "detail.tool: {s}"
    );
    let (position, _) = check_against_kinematics(&kin, &s);

    let o = &s["cartesian_state"]["orientation"];
    let ik = c.request(
        &serde_json::json!({"command": "inverse_kinematics", "arguments": {
            "position": position, "orientation": o}})
        .to_string(),
    );
    assert_eq!(ik["result_type"], "inverse_kinematics", "{ik}");
    let first: [f64; 6] = numbers(&ik["solutions"][0]);
    // The reported figures are rounded to 6 decimals: the pose, and so the solution, to ~1e-4 deg.
    assert!(
        distance(&first, &target) < 1e-3,
        "the present position first: {first:?}, target {target:?}: {ik}"
    );
}

/// The orientation check itself: a quaternion as a `status` writes it (rounded to 6 decimals,
/// so of norm 1 only to about 1e-7) is the same orientation as itself normalised, and a turn
/// about z is measured as that turn, either sign.
#[test]
fn the_orientation_check_reads_rounded_quaternions() {
    // A figure a status gave (norm 0.99999988); `2 acos(dot)` would read 1e-3 rad here.
    let rounded = [-0.00213, -1e-6, -0.999967, 0.007811];
    let n = rounded.iter().map(|x| x * x).sum::<f64>().sqrt();
    let exact = rounded.map(|x| x / n);
    assert!(orientation_angle(&rounded, &exact) < 1e-12);
    let half = 0.15_f64;
    let turned = [0.0, 0.0, half.sin(), half.cos()];
    let identity = [0.0, 0.0, 0.0, 1.0];
    assert!((orientation_angle(&identity, &turned) - 0.3).abs() < 1e-12);
    assert!((orientation_angle(&identity, &turned.map(|x| -x)) - 0.3).abs() < 1e-12);
}
