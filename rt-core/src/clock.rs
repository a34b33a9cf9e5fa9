//! The monotonic clock and absolute-deadline sleeping.
//!
//! Runs inside the cycle: `now_ns` is a vDSO call; `sleep_until_ns` is the one place the cycle
//! thread blocks, by design, between two cycles.

/// `CLOCK_MONOTONIC` in nanoseconds (the same clock as Python's `time.monotonic_ns()`).
pub fn now_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; CLOCK_MONOTONIC always exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// `CLOCK_REALTIME` in nanoseconds since the Unix epoch (for log file timestamps only).
pub fn realtime_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: as above, for CLOCK_REALTIME.
    unsafe { libc::clock_gettime(libc::CLOCK_REALTIME, &mut ts) };
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// Sleep until the absolute `CLOCK_MONOTONIC` time `deadline_ns` (`clock_nanosleep` with
/// `TIMER_ABSTIME`), resuming after signals. Returns at once if the deadline has passed.
pub fn sleep_until_ns(deadline_ns: u64) {
    let ts = libc::timespec {
        tv_sec: (deadline_ns / 1_000_000_000) as libc::time_t,
        tv_nsec: (deadline_ns % 1_000_000_000) as libc::c_long,
    };
    loop {
        // SAFETY: `ts` is a valid timespec; the remaining-time pointer may be null with
        // TIMER_ABSTIME.
        let rc = unsafe {
            libc::clock_nanosleep(
                libc::CLOCK_MONOTONIC,
                libc::TIMER_ABSTIME,
                &ts,
                core::ptr::null_mut(),
            )
        };
        if rc != libc::EINTR {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn monotonic_and_sleep_until_past_returns() {
        let a = now_ns();
        sleep_until_ns(a.saturating_sub(1_000_000));
        let b = now_ns();
        assert!(b >= a);
        sleep_until_ns(b + 200_000);
        assert!(now_ns() >= b + 200_000, "woke before the deadline");
    }
}
