//! The SocketCAN backend through a real kernel: the host's kernel has no CAN, so this boots the
//! test guest (tests/common/vm.rs: Debian's kernel with vcan, in QEMU) and runs there the unit
//! test of `bus/src/socketcan/tests.rs` that talks to a real interface, with
//! `MCM_TEST_CAN_IFACE=vcan0`: frames both ways between two sockets, skipped frames, the
//! deadline of `recv`, a burst of non-blocking sends. The test binary is built on the host and
//! shared into the guest; the test must report that it ran and passed (`--exact`: 1 passed, and
//! not the line it prints when it skips).

mod common;

use common::vm;
use std::time::Duration;

/// The unit test, by its full name.
const UNIT_TEST: &str = "socketcan::tests::real_interface_round_trip_when_available";

#[test]
fn the_socketcan_unit_test_passes_on_vcan0_in_the_guest() {
    let image = match vm::image() {
        Ok(image) => image,
        Err(why) => return common::skip("vm_socketcan", &why),
    };
    let test_binary = vm::lib_test_binary("mcm-bus");
    let mut guest = vm::Guest::boot("socketcan", &image, &vm::target_dir(), &[]);
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

    let status = guest.shutdown();
    assert!(status.success(), "QEMU ended with {status} (log: {log})");
}
