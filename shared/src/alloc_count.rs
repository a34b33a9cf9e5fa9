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
//! Without [`CountingAlloc`] installed nothing is counted: every figure stays 0.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

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
    // `try_with`: an allocation while the thread is torn down is not counted, never a panic
    // inside the allocator.
    if COUNTING.try_with(Cell::get).unwrap_or(false) {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        let _ = BYTES.try_with(|c| c.set(c.get() + size as u64));
    }
}

// SAFETY: every method forwards to the system allocator with the caller's arguments unchanged,
// so `System` upholds `GlobalAlloc`'s contract; the counting only touches const-initialised
// thread-locals of `Copy` data, which never allocate and never unwind.
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

/// Switch counting on (`true`) or off for the calling thread.
pub fn set_counting(on: bool) {
    COUNTING.with(|c| c.set(on));
}

/// Everything the calling thread counted so far (while its counting was on).
pub fn counted() -> Counts {
    Counts {
        allocations: ALLOCATIONS.with(Cell::get),
        bytes: BYTES.with(Cell::get),
    }
}

/// Run `f` with counting on for the calling thread: its result and what the thread allocated
/// meanwhile. Counting is then as it was before.
pub fn count<R>(f: impl FnOnce() -> R) -> (R, Counts) {
    let was = COUNTING.with(Cell::get);
    let before = counted();
    set_counting(true);
    let r = f();
    set_counting(was);
    (r, counted() - before)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_the_allocator_installed_nothing_is_counted() {
        let (v, counts) = count(|| vec![1u8; 100]);
        assert_eq!(v.len(), 100);
        assert_eq!(counts, Counts::default());
    }
}
