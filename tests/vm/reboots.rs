//! The emulator's reboots counted, by hand (ignored in the test run): `MCM_VM_REBOOTS` (20 by
//! default) reboots of one guest in a row, each a cold boot as [`vm::Guest::reboot`] does it,
//! each checked as the package test checks its reboot (the boot completed, vcan0 up). It fails
//! when QEMU crashed even once, also where the harness's one retry of a boot saved the test
//! (docs/testing.md, "The virtual machine": the command, run with the test command beside it).

use crate::common::{self, vm};
use std::time::{Duration, Instant};

/// How many reboots unless `MCM_VM_REBOOTS` says otherwise.
const REBOOTS: u32 = 20;

#[test]
#[ignore = "by hand, 15 to 30 minutes: docs/testing.md, \"The virtual machine\""]
fn reboots_in_a_row() {
    let image = match vm::image() {
        Ok(image) => image,
        Err(why) => return common::skip("vm reboots", &why),
    };
    let reboots: u32 = common::env_or("MCM_VM_REBOOTS", REBOOTS);
    let mut guest = vm::Guest::boot("reboots", &image, &vm::target_dir(), &[]);
    let mut took: Vec<Duration> = Vec::new();
    for i in 1..=reboots {
        let started = Instant::now();
        guest.reboot();
        guest.check_rebooted();
        took.push(started.elapsed());
        eprintln!(
            "reboot {i}/{reboots}: running again after {:.1} s",
            started.elapsed().as_secs_f64()
        );
    }
    took.sort();
    if let (Some(first), Some(last)) = (took.first(), took.last()) {
        eprintln!(
            "{reboots} reboots: {:.1} s fastest, {:.1} s median, {:.1} s slowest; QEMU crashed {} times",
            first.as_secs_f64(),
            took[took.len() / 2].as_secs_f64(),
            last.as_secs_f64(),
            guest.emulator_crashes()
        );
    }
    assert_eq!(
        guest.emulator_crashes(),
        0,
        "QEMU crashed during the reboots (each boot it crashed in was started once more); log: {}",
        guest.log().display()
    );
    let log = guest.log().display().to_string();
    let status = guest.shutdown();
    assert!(status.success(), "QEMU ended with {status} (log: {log})");
}
