//! `mcm-ros2 --ros2-read-only` against real ROS 2: rclpy of Kilted (PyPI wheels, Fast DDS) in a
//! network namespace of its own, with its own `ROS_DOMAIN_ID`, as `ros2.rs` does. The checks are
//! `tests/ros2/read_only_checks.py`.

use crate::common;
use crate::ros2::expect_checks;

use common::netns::Netns;
use common::ros2::{self, Distro, mcm_in};

use std::time::Duration;

/// A read-only node on a calibrated arm that nobody controls (so any motion interface would
/// move it): rclpy reads the joint states; the ROS graph shows the node's publishers and no
/// service, no action server, no `joint_trajectory` subscription; an action client finds no
/// server; a `JointTrajectory` published on `joint_trajectory` leaves the arm's true position
/// unchanged over 400 of the robot's cycles; the graph, looked at again seconds later, still
/// shows no motion interface; `/diagnostics` says the node offers none.
#[test]
fn a_read_only_node_offers_no_motion_interface() {
    let test = "a_read_only_node_offers_no_motion_interface";
    let Some(py) = ros2::venv_or_skip(test, Distro::Kilted) else {
        return;
    };
    let Some(ns) = Netns::or_skip(test, "readonly") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let instance = common::unique_instance("ros2ro");
    let mcm = mcm_in(
        &ns,
        &instance,
        Distro::Kilted,
        &[format!("--domain-id={domain}"), "--ros2-read-only".into()],
    );
    let _json = ros2::calibrated_client(&ns, &mcm);
    let json_addr = mcm.json.to_string();
    let lines = ros2::run_in(
        &ns,
        &py,
        domain,
        &ros2::dir().join("read_only_checks.py"),
        &["--json", &json_addr],
        Duration::from_secs(120),
    );
    expect_checks(
        &lines,
        &[
            "joint_states",
            "graph",
            "no_action_server",
            "joint_trajectory_ignored",
            "graph_later",
            "diagnostics_read_only",
        ],
    );
}
