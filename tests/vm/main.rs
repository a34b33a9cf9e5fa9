//! The tests that need a real Linux kernel (this machine's has no CAN) or systemd as PID 1, in
//! one boot of the test guest (tests/common/vm.rs: Debian 13 under QEMU's software emulation,
//! docs/testing.md, "The virtual machine"). One executable with one test, because a boot is the
//! dearest part (half a minute to a minute under emulation) and the parts run one after another
//! anyway: they need the machine's cores for the MCM's timing inside the guest, so this
//! executable runs alone, as cargo runs every test executable.
//!
//! In order, in the same guest:
//! 1. the guest itself, what the parts rely on (`vm::check_the_guest`: systemd, vcan0, both
//!    CPUs online, the shares, no way to the host);
//! 2. [`socketcan`]: the SocketCAN backend's unit test and the MCM's end-to-end tests over the
//!    kernel's CAN with the virtual arm, in the guest as built (the kernel's real-time
//!    throttling on, as on any fresh machine; the package below turns it off); it removes what
//!    its MCMs, run as root, left in `/tmp` and `/dev/shm`;
//! 3. [`package`]: the Debian package installed, run under systemd, restarted, stopped,
//!    rebooted (a cold boot), upgraded and purged (nothing left behind).
//!
//! Beside it, the harness's answer to QEMU crashing, with a stand-in for QEMU ([`emulator_crash`]).
//! By hand, ignored in the test run: `socketcan::soak_in_the_guest` (ten minutes of motion over
//! SocketCAN) and `reboots::reboots_in_a_row` (the emulator's reboots counted). A missing tool
//! (QEMU, or debootstrap and root to build the guest; cargo-deb) skips, or fails with CI set.

#[path = "../common/mod.rs"]
mod common;

mod emulator_crash;
mod package;
mod reboots;
mod socketcan;

use common::vm;

#[test]
fn in_one_guest_socketcan_the_mcm_over_it_then_the_debian_package_under_systemd() {
    let image = match vm::image() {
        Ok(image) => image,
        Err(why) => return common::skip("vm", &why),
    };
    let debs = match package::packages() {
        Ok(debs) => debs,
        Err(why) => return common::skip("vm", &why),
    };
    let mut guest = vm::Guest::boot("vm", &image, &vm::target_dir(), &package::FORWARDED);
    let log = guest.log().display().to_string();
    vm::check_the_guest(&mut guest);
    socketcan::run(&mut guest);
    package::run(&mut guest, &debs);
    let status = guest.shutdown();
    assert!(status.success(), "QEMU ended with {status} (log: {log})");
}
