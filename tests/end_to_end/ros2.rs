//! The ROS 2 node against real ROS 2: rclpy (PyPI wheels, Fast DDS) in the test's venv talks
//! to `mcm --ros2` on the simulated arm (docs/ros2.md).
//!
//! Each test makes its own network namespaces (`common::netns`), so DDS's multicast discovery
//! stays inside them and no other test's participants are found; each also has its own
//! `ROS_DOMAIN_ID`. The checks themselves are `tests/ros2/node_checks.py` (real rclpy, with
//! control_msgs built from its real definitions); this file starts the MCM and the script in
//! the namespaces and fails with the script's output.

use crate::common;

use common::Client;
use common::netns::Netns;
use common::ros2::{self, Distro, mcm_in};
use mcm_client::launch::SimulatedMcm;
use std::path::Path;
use std::time::Duration;

/// How long the whole script may take (calibration included).
const SCRIPT_WITHIN: Duration = Duration::from_secs(300);

/// Run `node_checks.py args` in `ns` ([`ros2::run_in`]); returns its `ok ...` lines.
fn run_checks(ns: &Netns, py: &Path, domain: u32, args: &[&str]) -> Vec<String> {
    let script = ros2::dir().join("node_checks.py");
    let lines = ros2::run_in(ns, py, domain, &script, args, SCRIPT_WITHIN);
    lines.into_iter().filter(|l| l.starts_with("ok ")).collect()
}

/// Every check of `names` reported `ok NAME ...` among a script's `lines`.
pub(crate) fn expect_checks(lines: &[String], names: &[&str]) {
    for n in names {
        assert!(
            lines.iter().any(|l| l.starts_with(&format!("ok {n}"))),
            "check {n} did not report ok: {lines:#?}"
        );
    }
}

/// One arm, seen by rclpy of Kilted: joint states against the truth, the URDF, the services,
/// the diagnostics, goals (shuffled joints, invalid ones, before calibration, cancel,
/// preemption, another client's hold and control), and the streaming topic; the feedback
/// decoded by control_msgs 6.8.0, with its point `index`.
#[test]
fn rclpy_drives_the_simulated_arm() {
    rclpy_of_drives_the_simulated_arm("rclpy_drives_the_simulated_arm", Distro::Kilted);
}

/// The same checks with rclpy of Jazzy (PyPI's `ros-jazzy-*` wheels) against the node started
/// with `--ros-distro jazzy`: the feedback decoded by Jazzy's own control_msgs (5.8.0, without
/// `index`).
#[test]
fn rclpy_of_jazzy_drives_the_simulated_arm() {
    rclpy_of_drives_the_simulated_arm("rclpy_of_jazzy_drives_the_simulated_arm", Distro::Jazzy);
}

fn rclpy_of_drives_the_simulated_arm(test: &str, distro: Distro) {
    let Some(py) = ros2::venv_or_skip(test, distro) else {
        return;
    };
    let Some(ns) = Netns::or_skip(test, "one") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let instance = common::unique_instance("ros2");
    let mcm = mcm_in(&ns, &instance, distro, &[format!("--domain-id={domain}")]);
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
            "safety_error",
            "services",
        ],
    );
    // The client's control_msgs is the distribution's: 6.x has the feedback's point index.
    let fjt = ok
        .iter()
        .find(|l| l.starts_with("ok follow_joint_trajectory"))
        .expect("checked above");
    let want = match distro {
        Distro::Jazzy => "feedback_index=absent",
        Distro::Kilted => "feedback_index=0..",
    };
    assert!(fjt.contains(want), "{distro:?}: want {want} in {fjt:?}");
}

/// Two arms under `/left` and `/right` on one host, driven from another host (a second
/// namespace joined by a veth pair): DDS across the "network".
#[test]
fn two_arms_from_another_host() {
    let test = "two_arms_from_another_host";
    let Some(py) = ros2::venv_or_skip(test, Distro::Kilted) else {
        return;
    };
    let Some(robot) = Netns::or_skip(test, "robot") else {
        return;
    };
    let Some(desk) = Netns::or_skip(test, "desk") else {
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
                Distro::Kilted,
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

/// A second DDS implementation reads the node's joint states: Cyclone DDS's Python binding (no
/// ROS, `tests/ros2/cyclone_joint_states.py`) against the node's RustDDS, discovering it by
/// multicast inside the namespace; the positions it decodes are the MCM's.
#[test]
fn cyclone_dds_reads_the_joint_states() {
    let test = "cyclone_dds_reads_the_joint_states";
    let Some(py) = ros2::venv_or_skip(test, Distro::Kilted) else {
        return;
    };
    let Some(ns) = Netns::or_skip(test, "cyclone") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let instance = common::unique_instance("cyclone");
    let mcm = mcm_in(
        &ns,
        &instance,
        Distro::Kilted,
        &[format!("--domain-id={domain}")],
    );
    let mut json = Client::on(
        ns.connect(mcm.json)
            .expect("connect to the JSON port in the ns"),
    );
    // At rest with the drives online: the measured positions hold still.
    json.wait_drives_online();
    let script = ros2::dir().join("cyclone_joint_states.py");
    let domain_arg = domain.to_string();
    let lines = ros2::run_in(
        &ns,
        &py,
        domain,
        &script,
        &["--domain", &domain_arg, "--count", "50"],
        SCRIPT_WITHIN,
    );
    let out = lines.join("\n");
    assert!(out.contains("ok cyclone_joint_states messages="), "{out}");
    ros2::assert_read_the_arm(&out, &mut json);
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
    let Some(ns) = Netns::or_skip(test, "restart") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let instance = common::unique_instance("ros2r");
    let mcm = mcm_in(
        &ns,
        &instance,
        Distro::Kilted,
        &[format!("--domain-id={domain}")],
    );
    let first = node_pid(&instance).expect("the node's process");
    let rt_pid = mcm.rt_pid;
    let mut json = Client::on(
        ns.connect(mcm.json)
            .expect("the JSON port, from the namespace"),
    );
    let cycle = |json: &mut Client| {
        json.request(r#"{"command":"status","arguments":{"detail":true}}"#)["detail"]["cycle"]
            .as_u64()
            .expect("cycle")
    };
    let before = cycle(&mut json);
    // SAFETY: kill(2) on a pid this test found to be the node's; no memory is involved.
    assert_eq!(unsafe { libc::kill(first, libc::SIGKILL) }, 0);
    let line = mcm
        .wait_line("mcm-ros2 ready", Duration::from_secs(30))
        .expect("the node's ready line again");
    assert!(line.contains(&format!("instance={instance}")), "{line}");
    let second = node_pid(&instance).expect("the restarted node's process");
    assert_ne!(first, second, "a new process");
    let after = cycle(&mut json);
    assert!(after > before, "the core kept cycling: {before} -> {after}");
    assert!(
        std::path::Path::new(&format!("/proc/{rt_pid}")).exists(),
        "mcm-rt still runs"
    );
}

/// A reader that stops (a paused process, SIGSTOP) does not hold up another: the other still
/// gets every state, counted on the stamps (the robot's cycle times). DDS is reliable here
/// (rclpy's default), so the node's writer must not wait for the stopped reader.
#[test]
fn a_stopped_reader_does_not_hold_up_another() {
    let test = "a_stopped_reader_does_not_hold_up_another";
    let Some(py) = ros2::venv_or_skip(test, Distro::Kilted) else {
        return;
    };
    let Some(ns) = Netns::or_skip(test, "stall") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let instance = common::unique_instance("ros2s");
    let _mcm = mcm_in(
        &ns,
        &instance,
        Distro::Kilted,
        &[format!("--domain-id={domain}")],
    );
    let script = ros2::dir().join("reader_rate.py");
    let reader = |seconds: &str| {
        let (_, child, lines) = ros2::spawn_in(
            &ns,
            &py,
            domain,
            &script,
            &["--period", "0.005", "--window", "2", "--seconds", seconds],
        );
        (child, lines)
    };
    let line = |rx: &std::sync::mpsc::Receiver<String>, what: &str| {
        rx.recv_timeout(Duration::from_secs(30))
            .unwrap_or_else(|e| panic!("{what}: {e}"))
    };
    let (mut stopped, stopped_lines) = reader("60");
    let (mut watching, watching_lines) = reader("40");
    assert_eq!(line(&stopped_lines, "the reader to stop is ready"), "ready");
    assert_eq!(
        line(&watching_lines, "the watching reader is ready"),
        "ready"
    );
    // SAFETY: kill(2) on a child of this test.
    unsafe { libc::kill(stopped.id() as i32, libc::SIGSTOP) };
    // The first window may have begun before the stop; the next five (10 s) are all after it.
    let _ = line(&watching_lines, "a first window");
    let mut windows = Vec::new();
    for _ in 0..5 {
        let l = line(&watching_lines, "a window of the watching reader");
        let num = |key: &str| -> u64 {
            l.split_whitespace()
                .find_map(|w| w.strip_prefix(key))
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("{key} in {l:?}"))
        };
        windows.push((num("received="), num("cycles=")));
    }
    // SAFETY: as above.
    unsafe { libc::kill(stopped.id() as i32, libc::SIGCONT) };
    let _ = stopped.kill();
    let _ = watching.kill();
    let _ = (stopped.wait(), watching.wait());
    for (received, cycles) in &windows {
        assert!(
            *cycles >= 300 && *received as f64 >= 0.95 * *cycles as f64,
            "with a stopped reader, the other received {received} states over {cycles} cycles: {windows:?}"
        );
    }
}

/// Run `abuse_checks.py check --json ADDR args` in `ns` against a fresh arm; returns its lines.
fn run_abuse_check(
    ns: &Netns,
    py: &Path,
    domain: u32,
    check: &str,
    json: &str,
    args: &[&str],
) -> Vec<String> {
    let script = ros2::dir().join("abuse_checks.py");
    let mut all = vec![check, "--json", json];
    all.extend_from_slice(args);
    ros2::run_in(ns, py, domain, &script, &all, SCRIPT_WITHIN)
}

/// Wait for the first line of `rx` that `pred` accepts, at most `within`; the lines seen
/// instead when it does not come (the script failed, ended or hangs).
fn line_within(
    rx: &std::sync::mpsc::Receiver<String>,
    pred: impl Fn(&str) -> bool,
    within: Duration,
) -> Result<String, Vec<String>> {
    let deadline = std::time::Instant::now() + within;
    let mut seen = Vec::new();
    loop {
        let left = deadline.saturating_duration_since(std::time::Instant::now());
        match rx.recv_timeout(left) {
            Ok(l) if pred(&l) => return Ok(l),
            Ok(l) if l.starts_with("FAILED") => {
                seen.push(l);
                return Err(seen);
            }
            Ok(l) => seen.push(l),
            Err(_) => return Err(seen),
        }
    }
}

/// How many times [`the_node_survives_stop_and_continue`] stops the node: 100 with
/// `MCM_ROS2_STOP_CYCLES=100` (the figure in docs/ros2.md), fewer in the suite.
fn stop_cycles() -> u32 {
    common::env_or("MCM_ROS2_STOP_CYCLES", 20)
}

/// A node stopped and continued (Ctrl-Z, a debugger, `kill -STOP`/`-CONT`) during goals goes
/// on: the same process answers every goal and ends each with a result. Linux interrupts every
/// wait of a stopped process when it continues: the node's wait on the core and RustDDS's waits
/// for the network (patched, vendor/rustdds/MCM-PATCHES.md) go on.
#[test]
fn the_node_survives_stop_and_continue() {
    let test = "the_node_survives_stop_and_continue";
    let Some(py) = ros2::venv_or_skip(test, Distro::Kilted) else {
        return;
    };
    let Some(ns) = Netns::or_skip(test, "stopcont") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let instance = common::unique_instance("ros2sc");
    let mcm = mcm_in(
        &ns,
        &instance,
        Distro::Kilted,
        &[format!("--domain-id={domain}")],
    );
    let pid = node_pid(&instance).expect("the node's process");
    let until =
        std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{instance}.done"));
    let _ = std::fs::remove_file(&until);
    let script = ros2::dir().join("abuse_checks.py");
    let json = mcm.json.to_string();
    let until_arg = until.display().to_string();
    let (_, mut child, lines) = ros2::spawn_in(
        &ns,
        &py,
        domain,
        &script,
        &["stop_continue", "--json", &json, "--until", &until_arg],
    );
    line_within(&lines, |l| l == "calibrated", SCRIPT_WITHIN)
        .unwrap_or_else(|seen| panic!("the script did not get to its goals: {seen:#?}"));
    let cycles = stop_cycles();
    for cycle in 0..cycles {
        // SAFETY: kill(2) on the node's pid, found above; no memory is involved.
        assert_eq!(
            unsafe { libc::kill(pid, libc::SIGSTOP) },
            0,
            "the node (pid {pid}) exited after {cycle} stop/continue cycles"
        );
        // How long the node stays stopped and runs between stops: the pace of the abuse.
        std::thread::sleep(Duration::from_millis(100));
        // SAFETY: as above.
        assert_eq!(unsafe { libc::kill(pid, libc::SIGCONT) }, 0, "SIGCONT");
        std::thread::sleep(Duration::from_millis(200));
    }
    std::fs::write(&until, b"").expect("the script's stop file");
    let done = line_within(&lines, |l| l.starts_with("ok stop_continue"), SCRIPT_WITHIN);
    let _ = child.kill();
    let _ = child.wait();
    done.unwrap_or_else(|seen| panic!("not every goal ended with a result: {seen:#?}"));
    assert_eq!(
        node_pid(&instance),
        Some(pid),
        "the node exited after {cycles} stop/continue cycles (the launcher started another)"
    );
    let _ = std::fs::remove_file(&until);
}

/// A goal refused because a JSON client controls the arm changes nothing: that client's move,
/// running when the goal came, goes on to its target (docs/security.md).
#[test]
fn a_refused_goal_leaves_the_owners_move_alone() {
    let test = "a_refused_goal_leaves_the_owners_move_alone";
    let Some(py) = ros2::venv_or_skip(test, Distro::Kilted) else {
        return;
    };
    let Some(ns) = Netns::or_skip(test, "refused") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let instance = common::unique_instance("ros2rf");
    let mcm = mcm_in(
        &ns,
        &instance,
        Distro::Kilted,
        &[format!("--domain-id={domain}")],
    );
    let lines = run_abuse_check(&ns, &py, domain, "refused_goal", &mcm.json.to_string(), &[]);
    expect_checks(&lines, &["refused_goal"]);
}

/// How many 100,000-point goals [`oversize_goals_are_refused_naming_the_limit`] sends: 100
/// (the target of docs/ros2.md, about 40 s), or `MCM_ROS2_BIG_GOALS`.
fn big_goals() -> u32 {
    common::env_or("MCM_ROS2_BIG_GOALS", 100)
}

/// How far the node's resident memory may rise above its idle figure under a flood of
/// oversize goals (docs/ros2.md, limits).
const BIG_GOALS_RSS_MARGIN_KB: u64 = 20 * 1024;

/// The resident memory of process `pid` in kB (`VmRSS` of `/proc/PID/status`).
fn rss_kb(pid: i32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status"))
        .unwrap_or_else(|e| panic!("/proc/{pid}/status: {e}"));
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap_or_else(|| panic!("no VmRSS in /proc/{pid}/status: {status}"))
}

/// A goal over the size limits (docs/ros2.md: 10,000 points) is answered and ends with the
/// limit named, before the node plans anything; a flood of them, one after the other, leaves
/// the node's resident memory within [`BIG_GOALS_RSS_MARGIN_KB`] of its idle figure, read
/// after each goal's result.
#[test]
fn oversize_goals_are_refused_naming_the_limit() {
    let test = "oversize_goals_are_refused_naming_the_limit";
    let Some(py) = ros2::venv_or_skip(test, Distro::Kilted) else {
        return;
    };
    let Some(ns) = Netns::or_skip(test, "oversize") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let instance = common::unique_instance("ros2big");
    let _mcm = mcm_in(
        &ns,
        &instance,
        Distro::Kilted,
        &[format!("--domain-id={domain}")],
    );
    let pid = node_pid(&instance).expect("the node's process");
    let script = ros2::dir().join("abuse_checks.py");
    let count = big_goals();
    let count_arg = count.to_string();
    let (_, mut child, lines) = ros2::spawn_in(
        &ns,
        &py,
        domain,
        &script,
        &["big_goals", "--count", &count_arg, "--points", "100000"],
    );
    let started = std::time::Instant::now();
    line_within(&lines, |l| l == "ready", SCRIPT_WITHIN)
        .unwrap_or_else(|seen| panic!("the script did not get to its goals: {seen:#?}"));
    let idle = rss_kb(pid);
    let mut rss = Vec::new();
    for i in 0..count {
        let goal = format!("goal {i}");
        let ended = line_within(&lines, |l| l == goal, SCRIPT_WITHIN);
        let now = rss_kb(pid);
        rss.push(now);
        if ended.is_err() || now > idle + BIG_GOALS_RSS_MARGIN_KB {
            let _ = child.kill();
            let _ = child.wait();
        }
        ended.unwrap_or_else(|seen| panic!("big goal {i} did not end: {seen:#?}"));
        assert!(
            now <= idle + BIG_GOALS_RSS_MARGIN_KB,
            "the node's RSS rose from {idle} kB idle to {now} kB after {} goals of 100000 \
             points; allowed: at most {BIG_GOALS_RSS_MARGIN_KB} kB above idle (after each \
             goal, kB): {rss:?}",
            i + 1
        );
    }
    let done = line_within(&lines, |l| l.starts_with("ok big_goals"), SCRIPT_WITHIN);
    let _ = child.kill();
    let _ = child.wait();
    let done = done.unwrap_or_else(|seen| panic!("the goals were not refused: {seen:#?}"));
    assert!(
        done.contains("trajectory.points has 100000 entries; allowed: at most 10000"),
        "{done}"
    );
    eprintln!(
        "mcm-ros2 RSS: idle {idle} kB, after {count} goals of 100000 points {} kB, highest {} \
         kB, in {:.0} s",
        rss.last().copied().unwrap_or(idle),
        rss.iter().copied().max().unwrap_or(idle),
        started.elapsed().as_secs_f64()
    );
}

/// How many goals [`a_burst_of_goals_is_answered`] sends at once: 1,000 with
/// `MCM_ROS2_BURST=1000` (the figure in docs/ros2.md), fewer in the suite.
fn burst_goals() -> u32 {
    common::env_or("MCM_ROS2_BURST", 300)
}

/// A burst of goals sent at once by a client that keeps all its requests: the node answers
/// every goal (accepts it, or rejects it when its queue of goals is full) and ends every
/// accepted one with a result (docs/ros2.md, limits), and a JSON client's `hold` goes through
/// meanwhile.
#[test]
fn a_burst_of_goals_is_answered() {
    let test = "a_burst_of_goals_is_answered";
    let Some(py) = ros2::venv_or_skip(test, Distro::Kilted) else {
        return;
    };
    let Some(ns) = Netns::or_skip(test, "burst") else {
        return;
    };
    let domain = ros2::unique_domain_id();
    let instance = common::unique_instance("ros2burst");
    let mcm = mcm_in(
        &ns,
        &instance,
        Distro::Kilted,
        &[format!("--domain-id={domain}")],
    );
    let count = burst_goals().to_string();
    // A JSON client's `hold`s, timed before and during the burst (docs/performance.md).
    let lines = run_abuse_check(
        &ns,
        &py,
        domain,
        "burst",
        &mcm.json.to_string(),
        &["--count", &count, "--holds", "200"],
    );
    expect_checks(&lines, &["holds_idle", "holds_during_burst", "burst"]);
}
