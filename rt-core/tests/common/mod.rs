//! Set-up shared by the integration tests of mcm-rt-core: iceoryx2 peers of the core (a node,
//! the state blackboard's reader, the state event's listener), and the `mcm-rt` binary started
//! and stopped as a user runs it. Each test binary uses only part of it.

#![allow(dead_code)]

use iceoryx2::port::listener::Listener;
use iceoryx2::port::reader::Reader;
use iceoryx2::prelude::*;
use mcm_shared::service::ServiceNames;
use std::io::{BufRead, BufReader, Read};
use std::process::{Child, Command, ExitStatus, Stdio};

/// An iceoryx2 node of a test peer, without iceoryx2's signal handling (the test harness keeps
/// its own).
pub fn node() -> Node<ipc::Service> {
    NodeBuilder::new()
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .unwrap()
}

/// A reader of the state blackboard the core of `names` created.
pub fn state_reader(node: &Node<ipc::Service>, names: &ServiceNames) -> Reader<ipc::Service, u32> {
    node.service_builder(&names.state_service())
        .blackboard_opener::<u32>()
        .open()
        .expect("the core created the state service")
        .reader_builder()
        .create()
        .unwrap()
}

/// A listener of the state event the core of `names` created.
pub fn state_listener(node: &Node<ipc::Service>, names: &ServiceNames) -> Listener<ipc::Service> {
    node.service_builder(&names.state_event_service())
        .event()
        .open()
        .unwrap()
        .listener_builder()
        .create()
        .unwrap()
}

/// The `mcm-rt` binary of this build.
pub fn mcm_rt() -> Command {
    Command::new(env!("CARGO_BIN_EXE_mcm-rt"))
}

/// Start `cmd` with stdout and stderr piped; the child and the first line it printed (its ready
/// line, or empty if it ended first).
pub fn start(cmd: &mut Command) -> (Child, String) {
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut ready = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut ready)
        .unwrap();
    (child, ready)
}

/// Stop a child [`start`]ed with SIGTERM; its exit status and all it wrote on stderr.
pub fn stop(mut child: Child) -> (ExitStatus, String) {
    // SAFETY: kill only sends SIGTERM to the child started by this test.
    assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGTERM) }, 0);
    let status = child.wait().unwrap();
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    (status, err)
}

/// A CPU no machine has: pinning fails, so the set-up is not real-time on any machine.
pub const NO_CPU: usize = 100_000;

/// Options for `runner::run` in a test process: the P-Rob2's configuration (simulated), the
/// cycle pinned to [`NO_CPU`] and allowed to run without real time, the flight recorder in the
/// temporary directory, an instance of this test's own.
pub fn options(test: &str) -> mcm_rt_core::runner::RunOptions {
    let mut config = mcm_shared::config::RobotConfig::prob2_default();
    config.cycle.cpu = NO_CPU;
    config.safety.flight_recorder_dir = std::env::temp_dir().display().to_string();
    mcm_rt_core::runner::RunOptions {
        config,
        names: ServiceNames::new(&format!("{test}-{}", std::process::id())).unwrap(),
        allow_non_realtime: true,
        candump: None,
    }
}
