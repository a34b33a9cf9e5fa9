//! The test machine's CPUs, shared by the end-to-end tests that run side by side
//! (`tests/end_to_end/main.rs` runs several at once), or taken whole by a test whose assertions
//! depend on timing: a client's loop at the cycle rate, a share of answers applied in the next
//! cycle. Such a test calls [`alone`] first; it waits for the tests in flight to end and holds
//! off those that start meanwhile, then runs with the machine to itself while its guard lives.
//!
//! Every test that starts an MCM shares the machine without saying so: [`share`] is called by
//! [`super::unique_instance`] and by the MCM starts, and the share lasts until the test's thread
//! ends (the test harness runs each test on a thread of its own). A test that loads the machine
//! without an MCM (a C++ build, a Debian package) calls [`share`] itself.
//!
//! A test waiting to be alone holds off new shares, so that it gets its turn while the others
//! keep starting; a thread that already shares (the same test starting a second MCM) or that
//! is alone passes at once. Every wait is bounded ([`WAIT`]).

use std::cell::RefCell;
use std::sync::{Condvar, Mutex, MutexGuard};
use std::thread::ThreadId;
use std::time::{Duration, Instant};

/// The longest a test waits for its turn: the longest test of the executable and then some.
pub const WAIT: Duration = Duration::from_secs(15 * 60);

struct State {
    /// Threads sharing the machine.
    sharing: usize,
    /// The thread that has it alone.
    alone: Option<ThreadId>,
    /// Tests waiting to be alone.
    waiting: usize,
}

static STATE: Mutex<State> = Mutex::new(State {
    sharing: 0,
    alone: None,
    waiting: 0,
});
static CHANGED: Condvar = Condvar::new();

/// This thread's share, released when the thread ends.
struct Share;

impl Drop for Share {
    fn drop(&mut self) {
        lock().sharing -= 1;
        CHANGED.notify_all();
    }
}

thread_local! {
    static SHARE: RefCell<Option<Share>> = const { RefCell::new(None) };
}

/// Whether this thread shares the machine.
fn sharing() -> bool {
    SHARE.with(|s| s.borrow().is_some())
}

fn lock() -> MutexGuard<'static, State> {
    STATE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Wait on [`CHANGED`] while `blocked`; panics naming `what` after [`WAIT`].
fn wait_while(
    mut s: MutexGuard<'static, State>,
    what: &str,
    blocked: impl Fn(&State) -> bool,
) -> MutexGuard<'static, State> {
    let started = Instant::now();
    while blocked(&s) {
        let left = WAIT.checked_sub(started.elapsed()).unwrap_or_else(|| {
            panic!(
                "{what}: waited {WAIT:?} for the machine ({} tests sharing it, one alone: {})",
                s.sharing,
                s.alone.is_some()
            )
        });
        s = CHANGED
            .wait_timeout(s, left)
            .unwrap_or_else(|e| e.into_inner())
            .0;
    }
    s
}

/// This test shares the machine until its thread ends; waits while a test has it alone or is
/// waiting for it. Once per thread; later calls return at once.
pub fn share() {
    let me = std::thread::current().id();
    if sharing() {
        return;
    }
    let s = lock();
    if s.alone == Some(me) {
        return;
    }
    let mut s = wait_while(s, "sharing the machine", |s| {
        s.alone.is_some() || s.waiting > 0
    });
    s.sharing += 1;
    drop(s);
    SHARE.with(|s| *s.borrow_mut() = Some(Share));
}

/// The machine to this test alone while the guard lives.
#[must_use = "the machine is this test's only while the guard lives"]
pub struct Alone;

impl Drop for Alone {
    fn drop(&mut self) {
        lock().alone = None;
        CHANGED.notify_all();
    }
}

/// Wait until no other test runs, then keep the machine to this test while the guard lives.
/// Call it first, before starting anything.
pub fn alone() -> Alone {
    assert!(
        !sharing(),
        "alone() after this test started to share the machine: call it first"
    );
    lock().waiting += 1;
    // Counted until it has the machine, or until its wait panics.
    let waiting = Waiting;
    let mut s = wait_while(lock(), "alone on the machine", |s| {
        s.alone.is_some() || s.sharing > 0
    });
    s.alone = Some(std::thread::current().id());
    drop(s);
    drop(waiting);
    Alone
}

/// A test waiting to be alone.
struct Waiting;

impl Drop for Waiting {
    fn drop(&mut self) {
        lock().waiting -= 1;
        CHANGED.notify_all();
    }
}
