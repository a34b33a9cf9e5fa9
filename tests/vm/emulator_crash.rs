//! The harness's answer to QEMU crashing (tests/common/vm.rs), with a stand-in for QEMU and no
//! guest: a script that aborts (SIGABRT, as QEMU's failed assertion does) at the starts and
//! reboots it is told to, and otherwise plays the guest's agent (writes a new boot id, goes
//! down on `systemctl reboot`). A boot QEMU crashed in before the agent answered is started
//! once more and counted; a second crash in that boot fails, naming the emulator and quoting it.
//! Needs `qemu-img` (the overlay disk) only.

use crate::common::{self, vm};
use std::fs;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

/// What QEMU 10.0.2 printed when it aborted in a CI-like run.
const ASSERTION: &str = "qemu-system-x86_64: system/physmem.c:2678: iotlb_to_section: \
                         Assertion `section_index < d->map.sections_nb' failed.";

/// A directory of its own with a stand-in QEMU that crashes at the starts numbered in
/// `crash_at_start` (1: the first boot) and in the reboot of the boots numbered in
/// `crash_at_reboot`; and an "image" (an empty disk) for the overlay.
fn stand_in(test: &str, crash_at_start: &[u32], crash_at_reboot: &[u32]) -> (PathBuf, vm::Image) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(common::unique_instance(test));
    fs::create_dir_all(&dir).unwrap();
    let numbers = |n: &[u32]| n.iter().map(u32::to_string).collect::<Vec<_>>().join(" ");
    let script = format!(
        r#"#!/bin/bash
# A stand-in for QEMU (tests/vm/emulator_crash.rs).
for a in "$@"; do
    case "$a" in local,path=*,mount_tag=mcmrw*) rw=${{a#local,path=}}; rw=${{rw%%,*}};; esac
done
n=$(( $(cat "$rw/starts" 2>/dev/null || echo 0) + 1 ))
echo "$n" >"$rw/starts"
abort() {{ cat "$0.words" >&2; kill -ABRT $$; }}
case " {at_start} " in *" $n "*) abort;; esac
echo "boot-$n" >"$rw/agent/boot"
while sleep 0.05; do
    for c in "$rw"/agent/*.cmd; do
        if [ -e "$c" ] && grep -q reboot "$c"; then
            rm "$c"
            case " {at_reboot} " in *" $n "*) abort;; esac
            exit 0
        fi
    done
done
"#,
        at_start = numbers(crash_at_start),
        at_reboot = numbers(crash_at_reboot),
    );
    let program = dir.join("qemu-stand-in");
    fs::write(&program, script).unwrap();
    fs::write(dir.join("qemu-stand-in.words"), format!("{ASSERTION}\n")).unwrap();
    fs::set_permissions(&program, fs::Permissions::from_mode(0o755)).unwrap();
    let image = dir.join("image");
    fs::create_dir_all(&image).unwrap();
    fs::write(image.join("rootfs.img"), vec![0u8; 1 << 20]).unwrap();
    (program, vm::Image { dir: image })
}

fn boot(program: &Path, image: &vm::Image) -> vm::Guest {
    vm::Guest::boot_with(
        program.as_os_str(),
        "stand-in",
        image,
        image.dir.as_path(),
        &[],
    )
}

/// The panic's words of `f`, which must panic.
fn panic_words(f: impl FnOnce() + std::panic::UnwindSafe) -> String {
    let payload = std::panic::catch_unwind(f).expect_err("expected a panic");
    payload
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| payload.downcast_ref::<&str>().map(|s| (*s).to_owned()))
        .unwrap_or_default()
}

fn qemu_img_missing() -> bool {
    if common::find_program("qemu-img").is_none() {
        common::skip(
            "vm emulator_crash",
            "qemu-img is not installed (Debian: apt-get install qemu-utils)",
        );
        return true;
    }
    false
}

#[test]
fn a_boot_qemu_crashes_in_is_started_once_more_said_and_counted() {
    if qemu_img_missing() {
        return;
    }
    let (program, image) = stand_in("crash-once", &[1], &[]);
    let guest = boot(&program, &image);
    assert_eq!(guest.emulator_crashes(), 1);
    let log = fs::read_to_string(guest.log()).unwrap();
    assert!(
        log.contains("=== test harness: guest stand-in: QEMU itself crashed (signal: 6")
            && log.contains("not of the MCM")
            && log.contains(ASSERTION)
            && log.contains("starting QEMU once more"),
        "the console log does not say that QEMU crashed and was started again:\n{log}"
    );
}

#[test]
fn a_second_crash_in_the_same_boot_fails_naming_the_emulator() {
    if qemu_img_missing() {
        return;
    }
    let (program, image) = stand_in("crash-twice", &[1, 2], &[]);
    let words = panic_words(move || {
        boot(&program, &image);
    });
    assert!(
        words.contains("QEMU itself crashed (signal: 6")
            && words.contains("a fault of the emulator, not of the MCM or the guest")
            && words.contains(ASSERTION),
        "the failure does not name the emulator's crash: {words}"
    );
}

#[test]
fn a_crash_on_the_way_down_of_a_reboot_is_that_boot_s_one_crash() {
    if qemu_img_missing() {
        return;
    }
    let (program, image) = stand_in("crash-reboot", &[], &[1]);
    let mut guest = boot(&program, &image);
    guest.reboot();
    assert_eq!(guest.emulator_crashes(), 1);
    let (program, image) = stand_in("crash-reboot-and-boot", &[2], &[1]);
    let mut guest = boot(&program, &image);
    let words = panic_words(std::panic::AssertUnwindSafe(move || guest.reboot()));
    assert!(
        words.contains("QEMU itself crashed (signal: 6") && words.contains(ASSERTION),
        "the failure does not name the emulator's crash: {words}"
    );
}
