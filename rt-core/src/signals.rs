//! SIGINT and SIGTERM as a stop flag, for `mcm-rt` and the `mcm` launcher alike.
//!
//! Not in the cycle: [`install`] runs once at start-up (it allocates). The cycle loop only
//! loads the flag returned by [`stop_flag`], an atomic load. The handlers themselves are
//! `signal_hook::flag`'s, which only store to the atomic, and a counter increment
//! (async-signal-safe): the count tells a second signal (end a controlled stop at once) from
//! the first.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, LazyLock};

static STOP: LazyLock<Arc<AtomicBool>> = LazyLock::new(|| Arc::new(AtomicBool::new(false)));
static COUNT: AtomicUsize = AtomicUsize::new(0);

/// Make SIGINT and SIGTERM set the stop flag and count.
pub fn install() -> std::io::Result<()> {
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, Arc::clone(&STOP))?;
        // SAFETY: the action only increments a static atomic, which is async-signal-safe; it
        // neither allocates nor locks.
        unsafe {
            signal_hook::low_level::register(sig, || {
                COUNT.fetch_add(1, Ordering::SeqCst);
            })?;
        }
    }
    Ok(())
}

/// How many SIGINT/SIGTERM arrived since [`install`] (plus [`request_stop`] calls).
pub fn count() -> usize {
    COUNT.load(Ordering::SeqCst)
}

/// The flag that SIGINT and SIGTERM set; take it once before a loop that polls it.
pub fn stop_flag() -> &'static AtomicBool {
    &STOP
}

/// Whether a stop was asked for (by a signal or [`request_stop`]).
pub fn stop_requested() -> bool {
    stop_flag().load(Ordering::Relaxed)
}

/// Ask for a stop, as a signal would.
pub fn request_stop() {
    COUNT.fetch_add(1, Ordering::SeqCst);
    stop_flag().store(true, Ordering::SeqCst);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sigterm_sets_the_flag() {
        install().unwrap();
        assert!(!stop_requested());
        // SAFETY: raise only delivers a signal to this thread; the handler installed above
        // stores to an atomic and returns.
        let before = count();
        unsafe { libc::raise(libc::SIGTERM) };
        assert!(stop_requested());
        assert_eq!(count(), before + 1);
    }
}
