//! The ROS 2 examples (`examples/ros2/`, rclpy) run as a user runs them, against `mcm --ros2`
//! on the simulated arm, their output checked against the MCM's JSON view and the simulation's
//! ground truth (`sim`).
//!
//! Like `tests/end_to_end/ros2.rs`: the venv of `common::ros2` (rclpy from PyPI, control_msgs built
//! into it), the MCM and the examples inside a private network namespace of this test (DDS's
//! multicast stays in it), a domain of its own. The test's JSON client connects from inside the
//! namespace ([`Netns::connect`]). Without the tools the test is skipped, saying so, or fails when
//! `CI` is set.

use crate::common;

use common::netns::Netns;
use common::ros2::{self, Distro, joint_values, mcm_in};
use common::{Client, six};
use std::path::Path;
use std::time::Duration;

/// How long one example may take (`follow_trajectory.py` calibrates first: about 12 s).
const EXAMPLE_WITHIN: Duration = Duration::from_secs(180);

/// Run `examples/ros2/<name>.py args` in `ns`; its stdout.
fn example(ns: &Netns, py: &Path, domain: u32, name: &str, args: &[&str]) -> String {
    let script = common::python::repo_root()
        .join("examples/ros2")
        .join(format!("{name}.py"));
    ros2::run_in(ns, py, domain, &script, args, EXAMPLE_WITHIN).join("\n")
}

/// Each joint's position printed by `joint_states.py`: (name, rad, deg) of its lines
/// `  name  +0.1234 rad  +7.070 deg`.
fn printed_positions(out: &str) -> Vec<(String, f64, f64)> {
    out.lines()
        .filter(|l| l.ends_with(" deg") && l.contains(" rad "))
        .map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            let num = |s: &str| -> f64 { s.parse().unwrap_or_else(|e| panic!("{s:?}: {e}")) };
            (w[0].to_string(), num(w[1]), num(w[3]))
        })
        .collect()
}

#[test]
fn ros2_examples_drive_the_simulated_arm() {
    let test = "ros2_examples_drive_the_simulated_arm";
    let Some(py) = ros2::venv_or_skip(test, Distro::Kilted) else {
        return;
    };
    let Some(ns) = Netns::or_skip(test, "examples") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let d = format!("--domain-id={domain}");
    let instance = common::unique_instance("ros2ex");
    let mcm = mcm_in(&ns, &instance, Distro::Kilted, std::slice::from_ref(&d));
    // A second arm in the same domain under /left: the examples' --namespace and --instance
    // pick one of the two.
    let left = mcm_in(
        &ns,
        &common::unique_instance("ros2ex-left"),
        Distro::Kilted,
        &[d, "--namespace=/left".into(), "--joint-prefix=left_".into()],
    );
    let mut json = Client::on(
        ns.connect(mcm.json)
            .expect("connect to the JSON port in the ns"),
    );
    json.wait_drives_online();

    // Diagnostics, before calibration: a warning saying so, this instance's.
    let out = example(&ns, &py, domain, "diagnostics", &["--instance", &instance]);
    for words in [
        "level 1 (WARN): ".to_string(),
        ": not calibrated (call the calibrate service)".to_string(),
        format!(" (MCM instance {instance})"),
        "  all calibrated: false".to_string(),
        "  drives online: 6/6".to_string(),
    ] {
        assert!(out.contains(&words), "{words:?} not in: {out}");
    }

    // Joint states: every joint, in radians and degrees, where the MCM measures it (at rest).
    let out = example(
        &ns,
        &py,
        domain,
        "joint_states",
        &["--count", "2", "--every", "0.2"],
    );
    assert!(out.contains("joint_states 2/2"), "{out}");
    let printed = printed_positions(&out);
    let names = ["base", "shoulder", "elbow", "forearm", "wrist", "flange"];
    assert_eq!(printed.len(), 12, "2 messages of 6 joints: {out}");
    let status = json.request(r#"{"command":"status"}"#);
    let measured = six(&status["axis_states"]["position"]);
    for (i, (n, rad, deg)) in printed[6..].iter().enumerate() {
        assert_eq!(n, names[i], "{out}");
        assert!(
            (rad.to_degrees() - deg).abs() < 0.01,
            "{n}: {rad} rad vs {deg} deg"
        );
        assert!(
            (deg - measured[i]).abs() < 0.01,
            "{n} printed at {deg} deg, the MCM measures {} deg: {out}",
            measured[i]
        );
    }
    let out = example(
        &ns,
        &py,
        domain,
        "joint_states",
        &["--namespace", "/left", "--count", "1"],
    );
    let left_names: Vec<String> = printed_positions(&out).into_iter().map(|p| p.0).collect();
    assert_eq!(
        left_names,
        names.map(|n| format!("left_{n}")),
        "the /left arm's joints: {out}"
    );

    // The trajectory: refused (not calibrated), calibrated, then run to its target.
    let out = example(
        &ns,
        &py,
        domain,
        "follow_trajectory",
        &["--offset", "10", "--duration", "2"],
    );
    assert!(out.contains("not calibrated"), "{out}");
    assert!(out.contains("calibrate: success=True"), "{out}");
    assert!(out.contains("  feedback t="), "{out}");
    assert!(
        out.contains("result: error_code 0 (SUCCESSFUL), error_string ''"),
        "{out}"
    );
    let target = joint_values(&out, "target: ");
    let at = joint_values(&out, "at: ");
    let (truth, _) = json.truth();
    assert_eq!(target.len(), 6, "{out}");
    for (i, ((n, want), (_, got))) in target.iter().zip(&at).enumerate() {
        assert_eq!(n, names[i], "{out}");
        assert!(
            (truth[i] - want).abs() < 0.2 && (got - want).abs() < 0.2,
            "{n}: target {want} deg, printed at {got} deg, truly at {} deg",
            truth[i]
        );
    }

    // Diagnostics after: calibrated, OK, the node holds control after its goal.
    let out = example(&ns, &py, domain, "diagnostics", &["--instance", &instance]);
    for words in [
        "level 0 (OK)",
        "  all calibrated: true",
        "  owner: this ROS 2 node",
    ] {
        assert!(out.contains(words), "{words:?} not in: {out}");
    }
    drop(left);
}
