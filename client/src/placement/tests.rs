use super::*;

/// The CPU the calling thread may run on, read back from the kernel.
fn allowed() -> Vec<usize> {
    // SAFETY: an all-zero cpu_set_t is the empty set.
    let mut set: libc::cpu_set_t = unsafe { std::mem::zeroed() };
    // SAFETY: `set` is writable and of the size passed; pid 0 is the calling thread.
    let rc =
        unsafe { libc::sched_getaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &mut set) };
    assert_eq!(rc, 0);
    (0..8 * std::mem::size_of::<libc::cpu_set_t>())
        // SAFETY: every index is below the set's capacity in bits.
        .filter(|&c| unsafe { libc::CPU_ISSET(c, &set) })
        .collect()
}

#[test]
fn a_thread_pinned_to_an_allowed_cpu_runs_there_only() {
    let cpu = *allowed().last().expect("this thread may run somewhere");
    std::thread::spawn(move || {
        pin_current_thread(cpu).unwrap();
        assert_eq!(allowed(), vec![cpu]);
    })
    .join()
    .unwrap();
}

#[test]
fn a_cpu_beyond_the_set_is_named_with_the_range() {
    let e = pin_current_thread(100_000).unwrap_err();
    assert_eq!(
        e,
        PinError::OutOfRange {
            cpu: 100_000,
            max: 1024
        }
    );
    assert_eq!(e.to_string(), "CPU 100000 cannot be named: allowed 0..1024");
}

#[test]
fn an_offline_cpu_is_refused_with_the_kernels_reason() {
    // CPU 1023 exists in no test machine.
    let e = std::thread::spawn(|| pin_current_thread(1023))
        .join()
        .unwrap()
        .unwrap_err();
    assert!(matches!(e, PinError::Refused { cpu: 1023, .. }), "{e}");
    assert!(e.to_string().contains("Invalid argument"), "{e}");
}
