//! The ROS 2 node against real ROS 2: rclpy (PyPI wheels, Fast DDS) in the test's venv talks
//! to `mcm --ros2` on the simulated arm (docs/ros2.md).
//!
//! Each test makes its own network namespaces (`common::netns`), so DDS's multicast discovery
//! stays inside them and no other test's participants are found; each also has its own
//! `ROS_DOMAIN_ID`. The checks themselves are `tests/ros2/node_checks.py` (real rclpy, with
//! control_msgs built from its real definitions); this file starts the MCM and the script in
//! the namespaces and fails with the script's output.

mod common;

use common::netns::Netns;
use common::ros2::{self, Discovery};
use mcm_client::launch::SimulatedMcm;
use std::ffi::OsStr;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Stdio};
use std::time::{Duration, Instant};

/// How long the whole script may take (calibration included).
const SCRIPT_WITHIN: Duration = Duration::from_secs(300);

/// A namespace, or `None` after saying the test is skipped (a failure under CI).
fn netns_or_skip(test: &str, tag: &str) -> Option<Netns> {
    match Netns::new(tag) {
        Ok(n) => Some(n),
        Err(e) => {
            common::skip(
                test,
                &format!("cannot make a network namespace (needs root and iproute2): {e}"),
            );
            None
        }
    }
}

/// Start the MCM with its ROS 2 node inside `ns`.
fn mcm_in(ns: &Netns, instance: &str, ros2_args: &[String]) -> SimulatedMcm {
    let binary = Path::new(env!("CARGO_BIN_EXE_mcm"));
    let mut extra: Vec<String> = vec!["--ros2".into()];
    extra.extend(ros2_args.iter().map(|a| format!("--ros2-arg={a}")));
    let extra: Vec<&OsStr> = extra.iter().map(OsStr::new).collect();
    SimulatedMcm::start_command(
        ns.command(binary),
        binary,
        instance,
        &extra,
        Stdio::inherit(),
        common::WAIT,
        Some("[mcm] "),
    )
    .unwrap_or_else(|e| panic!("start mcm --ros2 in {}: {e}", ns.name))
}

/// Run `node_checks.py args` in `ns`, echoing its lines; panics with them when it fails or
/// takes longer than [`SCRIPT_WITHIN`]. Returns its `ok ...` lines.
fn run_checks(ns: &Netns, py: &Path, domain: u32, args: &[&str]) -> Vec<String> {
    let mut cmd = ns.command(py);
    cmd.arg(ros2::dir().join("node_checks.py")).args(args);
    ros2::set_env(&mut cmd, domain, Discovery::Subnet);
    let mut child: Child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("run node_checks.py");
    let out = child.stdout.take().expect("piped");
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            eprintln!("[rclpy] {line}");
            let _ = tx.send(line);
        }
    });
    let deadline = Instant::now() + SCRIPT_WITHIN;
    let mut lines = Vec::new();
    loop {
        match rx.recv_timeout(Duration::from_millis(200)) {
            Ok(l) => lines.push(l),
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => break,
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "node_checks.py {args:?} took longer than {SCRIPT_WITHIN:?}; its lines: {lines:#?}"
            );
        }
    }
    let status = child.wait().expect("wait for node_checks.py");
    assert!(
        status.success(),
        "node_checks.py {args:?} failed ({status}); its lines: {lines:#?}"
    );
    lines.into_iter().filter(|l| l.starts_with("ok ")).collect()
}

fn expect_checks(lines: &[String], names: &[&str]) {
    for n in names {
        assert!(
            lines.iter().any(|l| l.starts_with(&format!("ok {n}"))),
            "check {n} did not report ok: {lines:#?}"
        );
    }
}

/// One arm, seen by rclpy: joint states against the truth, the URDF, the services, the
/// diagnostics, goals (shuffled joints, invalid ones, before calibration, cancel, preemption,
/// another client's hold and control), and the streaming topic.
#[test]
fn rclpy_drives_the_simulated_arm() {
    let test = "rclpy_drives_the_simulated_arm";
    let Some(py) = ros2::venv_or_skip(test) else {
        return;
    };
    let Some(ns) = netns_or_skip(test, "one") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let instance = common::unique_instance("ros2");
    let mcm = mcm_in(&ns, &instance, &[format!("--domain-id={domain}")]);
    let json = mcm.json.to_string();
    let ok = run_checks(&ns, &py, domain, &["single", "--json", &json]);
    expect_checks(
        &ok,
        &[
            "robot_description",
            "joint_states",
            "goal_before_calibration",
            "calibrate_service",
            "diagnostics",
            "joint_states_truth",
            "invalid_goals",
            "follow_joint_trajectory",
            "cancel",
            "preempt",
            "hold_from_json_client",
            "not_owner",
            "joint_trajectory_topic",
            "services",
        ],
    );
}

/// Two arms under `/left` and `/right` on one host, driven from another host (a second
/// namespace joined by a veth pair): DDS across the "network".
#[test]
fn two_arms_from_another_host() {
    let test = "two_arms_from_another_host";
    let Some(py) = ros2::venv_or_skip(test) else {
        return;
    };
    let Some(robot) = netns_or_skip(test, "robot") else {
        return;
    };
    let Some(desk) = netns_or_skip(test, "desk") else {
        return;
    };
    let net = (std::process::id() % 200) as u8 + 20;
    let (robot_addr, _) = Netns::link(&robot, &desk, net).expect("a veth pair between the hosts");
    let domain = ros2::unique_domain_id();
    let arms: Vec<SimulatedMcm> = ["left", "right"]
        .iter()
        .map(|side| {
            mcm_in(
                &robot,
                &common::unique_instance(side),
                &[
                    format!("--domain-id={domain}"),
                    format!("--namespace=/{side}"),
                    format!("--joint-prefix={side}_"),
                    format!("--dds-interface={robot_addr}"),
                ],
            )
        })
        .collect();
    let ok = run_checks(
        &desk,
        &py,
        domain,
        &[
            "remote",
            "--namespaces",
            "/left,/right",
            "--prefixes",
            "left_,right_",
            "--move",
            "/right",
        ],
    );
    expect_checks(&ok, &["remote_joint_states", "remote_goal"]);
    drop(arms);
}

/// The pid of the `mcm-ros2` process serving `instance` (its command line is `mcm-ros2 ros2
/// --instance NAME ...`, as the launcher starts it).
fn node_pid(instance: &str) -> Option<i32> {
    std::fs::read_dir("/proc").ok()?.flatten().find_map(|e| {
        let pid: i32 = e.file_name().to_str()?.parse().ok()?;
        let cmdline = std::fs::read(e.path().join("cmdline")).ok()?;
        let args: Vec<&[u8]> = cmdline.split(|b| *b == 0).collect();
        let is_node = args.first() == Some(&b"mcm-ros2".as_slice())
            && args
                .windows(2)
                .any(|w| w[0] == b"--instance" && w[1] == instance.as_bytes());
        is_node.then_some(pid)
    })
}

/// A node that dies is started again by the launcher, and the core, the gateway and the arm
/// go on meanwhile: the node is a client like any other.
#[test]
fn the_launcher_restarts_a_node_that_dies() {
    let test = "the_launcher_restarts_a_node_that_dies";
    let Some(ns) = netns_or_skip(test, "restart") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let instance = common::unique_instance("ros2r");
    let mcm = mcm_in(&ns, &instance, &[format!("--domain-id={domain}")]);
    let first = node_pid(&instance).expect("the node's process");
    let rt_pid = mcm.rt_pid;
    ns.enter()
        .expect("this thread into the namespace, where the gateway listens");
    let mut json = common::Client::connect(mcm.json);
    let before =
        json.request(r#"{"command":"status","arguments":{"detail":true}}"#)["detail"]["cycle"]
            .as_u64()
            .expect("cycle");
    // SAFETY: kill(2) on a pid this test found to be the node's; no memory is involved.
    assert_eq!(unsafe { libc::kill(first, libc::SIGKILL) }, 0);
    let line = mcm
        .wait_line("mcm-ros2 ready", Duration::from_secs(30))
        .expect("the node's ready line again");
    assert!(line.contains(&format!("instance={instance}")), "{line}");
    let second = node_pid(&instance).expect("the restarted node's process");
    assert_ne!(first, second, "a new process");
    let after =
        json.request(r#"{"command":"status","arguments":{"detail":true}}"#)["detail"]["cycle"]
            .as_u64()
            .expect("cycle");
    assert!(after > before, "the core kept cycling: {before} -> {after}");
    assert!(
        std::path::Path::new(&format!("/proc/{rt_pid}")).exists(),
        "mcm-rt still runs"
    );
}
