//! This test binary has no counting allocator installed: every entry point refuses to count.
//! (`shared/tests/alloc_count.rs` runs with it installed.)

use super::*;

#[test]
#[should_panic(expected = "add `#[global_allocator]")]
fn count_without_the_allocator_installed_panics() {
    let _ = count(|| vec![1u8; 100]);
}

#[test]
#[should_panic(expected = "CountingAlloc is not this program's global allocator")]
fn counted_without_the_allocator_installed_panics() {
    let _ = counted();
}

#[test]
#[should_panic(expected = "CountingAlloc is not this program's global allocator")]
fn set_counting_without_the_allocator_installed_panics() {
    set_counting(true);
}
