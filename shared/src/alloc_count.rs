//! A counting global allocator, for the tests that prove a path allocates nothing (the cycle,
//! the CANopen master, the C API's real-time functions).
//!
//! A test binary installs [`CountingAlloc`] as its global allocator; [`count`] then runs a
//! closure with counting switched on for the calling thread and returns what that thread
//! allocated meanwhile. The counters are per thread: tests running in parallel, and the test
//! harness's own threads, never disturb each other's figures. Where the counted stretch is not
//! one closure (a callback counting from its first call to its last), [`set_counting`] and
//! [`counted`] do the same in two steps.
//!
//! ```
//! use mcm_shared::alloc_count::{self, CountingAlloc};
//!
//! #[global_allocator]
//! static GLOBAL: CountingAlloc = CountingAlloc;
//!
//! fn main() {
//!     let (_, counts) = alloc_count::count(|| [0u8; 16].map(|b| b + 1));
//!     assert_eq!(counts.allocations, 0);
//!     let (v, counts) = alloc_count::count(|| vec![0u8; 16]);
//!     assert_eq!((counts.allocations, counts.bytes), (1, 16));
//!     // Each thread counts its own.
//!     let other = std::thread::spawn(move || alloc_count::count(|| v.repeat(4)).1);
//!     let theirs = other.join().unwrap();
//!     assert_eq!((theirs.allocations, theirs.bytes), (1, 64));
//!     assert_eq!(alloc_count::counted(), counts, "nothing more on this thread");
//! }
//! ```
//!
//! Without [`CountingAlloc`] installed nothing could be counted and "allocates nothing" would
//! pass whatever the code does: [`count`], [`counted`] and [`set_counting`] panic instead,
//! naming the missing `#[global_allocator]`.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, Ordering};

/// Set by [`CountingAlloc`] on its first call: it is the program's global allocator.
static INSTALLED: AtomicBool = AtomicBool::new(false);

/// What was counted on one thread: allocations (`alloc`, `alloc_zeroed`, `realloc`) and the
/// bytes they asked for (the new size, for a `realloc`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts {
    pub allocations: u64,
    pub bytes: u64,
}

impl std::ops::Sub for Counts {
    type Output = Counts;

    fn sub(self, earlier: Counts) -> Counts {
        Counts {
            allocations: self.allocations - earlier.allocations,
            bytes: self.bytes - earlier.bytes,
        }
    }
}

thread_local! {
    // `const` initialisation and `Copy` contents: reading or writing them never allocates (no
    // lazy initialisation) and they have no destructor, so the allocator may touch them.
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
    static BYTES: Cell<u64> = const { Cell::new(0) };
}

/// The system allocator, counting the allocations of each thread that switched counting on.
pub struct CountingAlloc;

/// Count one allocation of `size` bytes, if this thread counts.
fn note(size: usize) {
    if !INSTALLED.load(Ordering::Relaxed) {
        INSTALLED.store(true, Ordering::Relaxed);
    }
    // `try_with`: an allocation while the thread is torn down is not counted, never a panic
    // inside the allocator.
    if COUNTING.try_with(Cell::get).unwrap_or(false) {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        let _ = BYTES.try_with(|c| c.set(c.get() + size as u64));
    }
}

// SAFETY: every method forwards to the system allocator with the caller's arguments unchanged,
// so `System` upholds `GlobalAlloc`'s contract; the counting only touches an atomic flag and
// const-initialised thread-locals of `Copy` data, which never allocate and never unwind.
unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: forwarded unchanged; the caller upholds `alloc`'s contract.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: forwarded unchanged; the caller upholds `alloc_zeroed`'s contract.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note(new_size);
        // SAFETY: forwarded unchanged; the caller upholds `realloc`'s contract, and `ptr` came
        // from this allocator, i.e. from `System`.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged; `ptr` came from this allocator, i.e. from `System`.
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// Panic unless [`CountingAlloc`] is the program's global allocator: without it every count
/// would be 0, whatever was allocated.
fn require_installed() {
    if INSTALLED.load(Ordering::Relaxed) {
        return;
    }
    // Nothing went through it yet, or it is not installed: one allocation tells.
    drop(std::hint::black_box(Box::new(0u8)));
    assert!(
        INSTALLED.load(Ordering::Relaxed),
        "alloc_count: CountingAlloc is not this program's global allocator, so every count \
         would be 0; add `#[global_allocator] static GLOBAL: \
         mcm_shared::alloc_count::CountingAlloc = mcm_shared::alloc_count::CountingAlloc;` \
         to the test binary"
    );
}

/// Switch counting on (`true`) or off for the calling thread. Panics when [`CountingAlloc`]
/// is not the global allocator.
pub fn set_counting(on: bool) {
    require_installed();
    COUNTING.with(|c| c.set(on));
}

/// Everything the calling thread counted so far (while its counting was on). Panics when
/// [`CountingAlloc`] is not the global allocator.
pub fn counted() -> Counts {
    require_installed();
    Counts {
        allocations: ALLOCATIONS.with(Cell::get),
        bytes: BYTES.with(Cell::get),
    }
}

/// Puts the calling thread's counting back as it was when dropped, also by a panic.
struct Restore(bool);

impl Drop for Restore {
    fn drop(&mut self) {
        // `try_with`: never a second panic while the thread is torn down.
        let _ = COUNTING.try_with(|c| c.set(self.0));
    }
}

/// Run `f` with counting on for the calling thread: its result and what the thread allocated
/// meanwhile. Counting is then as it was before, also when `f` panics. Panics when
/// [`CountingAlloc`] is not the global allocator.
pub fn count<R>(f: impl FnOnce() -> R) -> (R, Counts) {
    let before = counted();
    let restore = Restore(COUNTING.with(Cell::get));
    set_counting(true);
    let r = f();
    drop(restore);
    (r, counted() - before)
}

#[cfg(test)]
mod tests;
