//! How the node gives back the memory of large received samples (glibc's allocator).
//!
//! A DDS peer chooses how large the samples it sends are: a goal of 100,000 points is 12.8 MB
//! on the wire. RustDDS reassembles such a sample in one block from the datagrams it came in,
//! and ros2-client copies it once more to decode it; the node refuses it for its size
//! (docs/ros2.md, limits) and all of it is freed. glibc would keep much of it:
//!
//! - it serves blocks of 128 KiB and more with an mmap of their own, returned when freed, but
//!   raises that threshold to the size of the largest such block freed (up to 32 MiB), so after
//!   the first large sample the next ones come from a heap, which keeps their pages;
//! - the datagrams a large sample arrives in (64 KiB each) leave free pages scattered in the
//!   receiving thread's heap, which glibc returns only from a heap's top.
//!
//! [`init`] fixes the threshold; [`give_back`] returns the free pages of every heap, after a
//! goal refused for its size. Together they keep the node's memory within 20 MB of its idle
//! figure across any number of such goals (`tests/end_to_end/ros2.rs`,
//! `oversize_goals_are_refused_naming_the_limit`).

/// Blocks from this size up are each an mmap of their own, given back when freed: every
/// sample larger than a datagram, and none of the node's per-cycle allocations.
#[cfg(target_env = "gnu")]
const MMAP_THRESHOLD: libc::c_int = 1 << 20;

/// Fix glibc's mmap threshold at [`MMAP_THRESHOLD`] (this also fixes its trim threshold at its
/// default); call once at the start, before the threads. A no-op on other C libraries.
pub fn init() {
    #[cfg(target_env = "gnu")]
    {
        // SAFETY: mallopt(3) only sets a parameter of the allocator, valid at any time; the
        // value is within glibc's range (at most 32 MiB on 64-bit).
        if unsafe { libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD) } == 0 {
            eprintln!(
                "mcm-ros2: glibc refused the mmap threshold {MMAP_THRESHOLD} B; large received \
                 samples may keep their memory (docs/ros2.md, limits)"
            );
        }
    }
}

/// Return the free pages of every heap of the process to the system. A no-op on other C
/// libraries.
pub fn give_back() {
    #[cfg(target_env = "gnu")]
    // SAFETY: malloc_trim(3) takes each heap's lock itself and only releases free memory.
    unsafe {
        libc::malloc_trim(0);
    }
}
