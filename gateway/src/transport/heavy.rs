//! The heavy lane: a long line (a big `pvt_points` batch, up to 64 KiB of JSON) takes
//! milliseconds of CPU to parse (about 2.5 ms on the benchmark machine, judging by the batches
//! the lane serves per second under the benchmark's flood). Sixty connections flooding such
//! lines would keep the async workers busy and delay every other connection's small command,
//! `hold` included, by tens of milliseconds. So a line longer than [`HEAVY_BYTES`] is parsed on
//! a blocking thread, one at a time for the whole gateway: a flood then keeps at most one CPU
//! busy, the waiting connections cost nothing (the lane is a semaphore, granted in arrival
//! order), and short commands never wait for it. After each long parse the lane stays closed as
//! long as the parse took (the caller has its result at once), so a flood of long lines uses at
//! most half of one CPU. The parsing thread runs `SCHED_IDLE`, so that the async workers and
//! the bridge get the CPU at once when they wake.

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
    let lane = LANE.acquire().await;
    let started = tokio::time::Instant::now();
    let parsed = tokio::task::spawn_blocking(move || {
        lower_priority();
        parse()
    })
    .await
    .ok();
    // The lane stays closed as long again (a flood of long lines gets at most half of one CPU
    // and leaves the rest to everything else); this caller goes on at once.
    let took = started.elapsed();
    tokio::spawn(async move {
        tokio::time::sleep(took).await;
        drop(lane);
    });
    parsed
}

thread_local! {
    /// The calling blocking-pool thread runs `SCHED_IDLE` already.
    static IDLE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Put the calling (blocking-pool) thread below every ordinary thread, `SCHED_IDLE`, once; it
/// keeps that for later parses. A higher nice value was not enough: the kernel (EEVDF) lets a
/// running thread finish its slice, so at nice 10 the bridge's wake-up for a `hold`'s answer
/// waited up to one whole parse (cycle start to result 2.3 to 2.7 ms at p99 under the
/// benchmark's flood); at `SCHED_IDLE` 0.9 to 1.4 ms.
fn lower_priority() {
    if IDLE.get() {
        return;
    }
    let idle = libc::sched_param { sched_priority: 0 };
    // SAFETY: sched_setscheduler(0, ..) sets only the calling thread's policy; the one pointer
    // passed is to a local `sched_param`.
    let set = unsafe { libc::sched_setscheduler(0, libc::SCHED_IDLE, &idle) };
    IDLE.set(set == 0);
}

#[cfg(test)]
mod tests;
