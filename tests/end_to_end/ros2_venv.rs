//! The ROS 2 test environment works (`tests/common/ros2.rs`): two rclpy processes from the
//! tests' venv on one ROS domain, discovering each other on loopback only, run
//! `tests/ros2/selfcheck.py`: a `control_msgs/action/FollowJointTrajectory` server (the type
//! built from the vendored definitions) with a `sensor_msgs/JointState` publisher, and a client
//! that sends a 2-point goal (feedback for both points, a SUCCESSFUL result naming what the
//! server got) and an empty one (aborted, INVALID_GOAL), and receives JointState messages.
//! Both load the type support of the node's other interfaces (String, DiagnosticArray, Trigger,
//! JointTrajectory) too.
//!
//! Without Python 3.11, cmake or a compiler the test is skipped, saying so, or fails when `CI`
//! is set; a pip install or build that fails fails it.

use crate::common;

use common::ros2::{self, Discovery, Distro};
use std::io::{BufRead, BufReader, Read};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// How long one rclpy process may take to start, or the client to do all its checks (each of
/// its own waits is bounded at 20 s too).
const LIMIT: Duration = Duration::from_secs(60);

/// A child process killed on drop (a failing test leaves none behind).
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Every line of `out`, as it comes, echoed to stderr with `prefix`.
fn lines(out: impl Read + Send + 'static, prefix: &'static str) -> mpsc::Receiver<String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            eprintln!("{prefix}{line}");
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

/// The line of `rx` starting with `prefix`, within `limit` (others are skipped).
fn wait_line(rx: &mpsc::Receiver<String>, prefix: &str, limit: Duration) -> String {
    let deadline = Instant::now() + limit;
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        match rx.recv_timeout(left) {
            Ok(line) if line.starts_with(prefix) => return line,
            Ok(_) => {}
            Err(e) => panic!("no line {prefix:?} within {limit:?} ({e})"),
        }
    }
}

/// Wait at most `limit` for `child` to exit (killed on drop otherwise).
fn wait_exit(child: &mut Killed, what: &str, limit: Duration) -> std::process::ExitStatus {
    let deadline = Instant::now() + limit;
    loop {
        if let Some(status) = child.0.try_wait().expect("wait for a child") {
            return status;
        }
        assert!(
            Instant::now() < deadline,
            "{what} did not exit within {limit:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Start `cmd` with its stdin and stdout piped; its stdout's lines, echoed as they come.
fn spawn(cmd: &mut Command, prefix: &'static str) -> (Killed, ChildStdin, mpsc::Receiver<String>) {
    let mut child = cmd
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap_or_else(|e| panic!("start {cmd:?}: {e}"));
    let stdin = child.stdin.take().expect("piped stdin");
    let out = lines(child.stdout.take().expect("piped stdout"), prefix);
    (Killed(child), stdin, out)
}

#[test]
fn rclpy_action_and_topic_between_two_processes() {
    let Some(py) = ros2::venv_or_skip(
        "rclpy_action_and_topic_between_two_processes",
        Distro::Kilted,
    ) else {
        return;
    };
    let script = ros2::dir().join("selfcheck.py");
    let domain = ros2::unique_domain_id();
    // ROS names take letters, digits and underscores.
    let tag = common::unique_instance("venv").replace('-', "_");
    let started = Instant::now();

    let (mut server, server_stdin, server_out) = spawn(
        ros2::command(&py, &script, domain, Discovery::Localhost).args(["server", &tag]),
        "[server] ",
    );
    wait_line(&server_out, "READY", LIMIT);

    let (mut client, client_stdin, client_out) = spawn(
        ros2::command(&py, &script, domain, Discovery::Localhost).args(["client", &tag]),
        "[client] ",
    );
    drop(client_stdin);
    let ok = wait_line(&client_out, "SELFCHECK OK", LIMIT);
    let status = wait_exit(&mut client, "the client", LIMIT);
    assert!(
        status.success(),
        "the client failed ({status}) after {ok:?}"
    );

    drop(server_stdin); // the server's signal to stop
    let served = wait_line(&server_out, "SERVED", LIMIT);
    let status = wait_exit(&mut server, "the server", LIMIT);
    assert!(status.success(), "the server failed ({status})");
    assert!(
        served.starts_with("SERVED goals=2 "),
        "the server should have served the client's 2 goals: {served:?}"
    );
    eprintln!(
        "ROS domain {domain}: {ok}; {served}; {:.1} s",
        started.elapsed().as_secs_f64()
    );
}
