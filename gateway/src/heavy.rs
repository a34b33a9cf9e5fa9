//! The heavy lane: a long line (a big `pvt_points` batch, up to 64 KiB of JSON) takes about a
//! millisecond of CPU to parse. Sixty connections flooding such lines would keep the async
//! workers busy and delay every other connection's small command, `hold` included, by tens
//! of milliseconds. So a line longer than [`HEAVY_BYTES`] is parsed on a blocking thread, one
//! at a time for the whole gateway: a flood then keeps at most one CPU busy, the waiting
//! connections cost nothing (the lane is a semaphore, granted in arrival order), and short
//! commands never wait for it. After each long parse the lane stays closed as long as the parse
//! took, so a flood of long lines uses at most half of one CPU. The parsing thread runs `SCHED_IDLE`,
//! so that the async workers and the bridge get the CPU at once when they wake.

use tokio::sync::Semaphore;

/// Lines longer than this go through the heavy lane.
pub const HEAVY_BYTES: usize = 4096;

static LANE: Semaphore = Semaphore::const_new(1);

/// Run `parse` for an input of `len` bytes: at once when it is short; in the heavy lane when it
/// is long. `None` only if the parse could not run to its end (a panic on the blocking
/// thread, which no input is known to cause).
pub async fn parse<T: Send + 'static>(
    len: usize,
    parse: impl FnOnce() -> T + Send + 'static,
) -> Option<T> {
    if len <= HEAVY_BYTES {
        return Some(parse());
    }
    // The lane is never closed, so acquiring cannot fail; were it to, parse all the same.
    let _lane = LANE.acquire().await;
    let started = tokio::time::Instant::now();
    let parsed = tokio::task::spawn_blocking(move || {
        lower_priority();
        parse()
    })
    .await
    .ok();
    // The lane stays closed as long again: a flood of long lines gets at most half of one CPU
    // and leaves the rest to everything else. A single batch is only delayed by its own
    // parse time.
    tokio::time::sleep(started.elapsed()).await;
    parsed
}

/// Nice value of a thread parsing in the heavy lane (it also runs `SCHED_IDLE`).
pub const HEAVY_NICE: libc::c_int = 10;

/// Put the calling (blocking-pool) thread below every ordinary thread: `SCHED_IDLE` (and nice
/// [`HEAVY_NICE`]); it keeps that for later parses. A lower nice value alone was not enough:
/// the kernel (EEVDF) lets a running thread finish its slice, so the bridge's wake-up for a
/// `hold`'s answer waited up to one whole parse (about 2.5 ms at p99 under a flood); a
/// `SCHED_IDLE` thread gives way at once (0.9 ms).
fn lower_priority() {
    // SAFETY: gettid, setpriority and sched_setscheduler only read and set the calling
    // thread's scheduling; the one pointer passed is to a local `sched_param`.
    unsafe {
        let tid = libc::syscall(libc::SYS_gettid) as libc::id_t;
        libc::setpriority(libc::PRIO_PROCESS, tid, HEAVY_NICE);
        let idle = libc::sched_param { sched_priority: 0 };
        libc::sched_setscheduler(tid as libc::pid_t, libc::SCHED_IDLE, &idle);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn short_and_long_inputs_are_both_parsed() {
        assert_eq!(parse(10, || 1 + 1).await, Some(2));
        assert_eq!(parse(HEAVY_BYTES + 1, || "long".len()).await, Some(4));
    }

    #[tokio::test]
    async fn long_inputs_are_parsed_below_every_ordinary_thread() {
        // SAFETY: sched_getscheduler only reads the calling thread's policy.
        let policy = || unsafe { libc::sched_getscheduler(0) };
        assert_eq!(parse(HEAVY_BYTES + 1, policy).await, Some(libc::SCHED_IDLE));
        assert_ne!(
            parse(10, policy).await,
            Some(libc::SCHED_IDLE),
            "short: inline"
        );
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn long_inputs_take_turns() {
        use std::sync::Arc;
        use std::sync::atomic::{AtomicUsize, Ordering};
        let (inside, most) = (Arc::new(AtomicUsize::new(0)), Arc::new(AtomicUsize::new(0)));
        let tasks: Vec<_> = (0..8)
            .map(|_| {
                let (inside, most) = (inside.clone(), most.clone());
                tokio::spawn(parse(HEAVY_BYTES * 2, move || {
                    let now = inside.fetch_add(1, Ordering::SeqCst) + 1;
                    most.fetch_max(now, Ordering::SeqCst);
                    std::thread::sleep(std::time::Duration::from_millis(5));
                    inside.fetch_sub(1, Ordering::SeqCst);
                }))
            })
            .collect();
        for t in tasks {
            assert_eq!(t.await.unwrap(), Some(()));
        }
        assert_eq!(most.load(Ordering::SeqCst), 1, "one heavy parse at a time");
    }
}
