//! A latency hint for the gateway's threads that answer clients (the tokio workers, the bridge
//! thread, and the ZeroMQ ROUTER and PUB threads): a short EEVDF slice ([`SLICE`]) through
//! `sched_setattr(2)`'s `sched_runtime`, for `SCHED_OTHER` threads on Linux 6.12 and later.
//!
//! The gateway stays an ordinary, non-real-time process (same policy, same nice value, no
//! privilege needed). What changes is when the kernel lets a thread of it run after a wake-up:
//! a thread with a shorter slice gets an earlier virtual deadline and preempts a thread with
//! the default slice (about 3 ms) at once, instead of waiting for that thread's slice to end.
//! That is the wait between the core's new state and a `hold`'s answer when other clients keep
//! the CPUs busy (see docs/performance.md). The threads do little work per wake-up, so they
//! get no more CPU time than before, only sooner. Older kernels ignore the hint.

use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// The slice asked for: the shortest the kernel accepts.
pub const SLICE: Duration = Duration::from_micros(100);

/// `struct sched_attr` of `sched_setattr(2)` (`SCHED_ATTR_SIZE_VER1`, 56 bytes).
#[repr(C)]
#[derive(Debug, Default, Clone, Copy)]
struct SchedAttr {
    size: u32,
    sched_policy: u32,
    sched_flags: u64,
    sched_nice: i32,
    sched_priority: u32,
    sched_runtime: u64,
    sched_deadline: u64,
    sched_period: u64,
    sched_util_min: u32,
    sched_util_max: u32,
}

// The kernel reads exactly `size` bytes of this layout: checked when compiling, not by a test.
const _: () = assert!(std::mem::size_of::<SchedAttr>() == 56);

/// The calling thread's scheduling attributes.
fn get() -> io::Result<SchedAttr> {
    let mut attr = SchedAttr::default();
    // SAFETY: sched_getattr(0, ..) writes at most `size` bytes into the live `attr`, which is
    // exactly that large.
    let r = unsafe {
        libc::syscall(
            libc::SYS_sched_getattr,
            0,
            &mut attr as *mut SchedAttr,
            std::mem::size_of::<SchedAttr>() as u32,
            0,
        )
    };
    if r < 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(attr)
}

/// Ask for [`SLICE`] for the calling thread, keeping its policy and nice value. Only for
/// `SCHED_OTHER` threads (others are left alone and get `Ok(false)`).
pub fn request_short_slice() -> io::Result<bool> {
    let mut attr = get()?;
    if attr.sched_policy != libc::SCHED_OTHER as u32 {
        return Ok(false);
    }
    attr.size = std::mem::size_of::<SchedAttr>() as u32;
    attr.sched_flags = 0;
    attr.sched_runtime = SLICE.as_nanos() as u64;
    // SAFETY: sched_setattr(0, ..) reads the live, fully initialised `attr` and changes only
    // the calling thread.
    let r = unsafe { libc::syscall(libc::SYS_sched_setattr, 0, &attr as *const SchedAttr, 0) };
    if r < 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(true)
}

/// [`request_short_slice`] for a thread starting; a failure is said once per process (the
/// gateway works without the hint, its answers may just come later under load).
pub fn on_thread_start() {
    static SAID: AtomicBool = AtomicBool::new(false);
    if let Err(e) = request_short_slice()
        && !SAID.swap(true, Ordering::Relaxed)
    {
        eprintln!(
            "mcm-gateway: could not ask for a {} us scheduler slice for its threads ({e}); \
             answers may come later while the CPUs are busy",
            SLICE.as_micros()
        );
    }
}

#[cfg(test)]
mod tests;
