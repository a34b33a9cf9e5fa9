//! The counting allocator installed: counts are per thread, and counting is put back as it was
//! when the counted closure panics.

use mcm_shared::alloc_count::{self, CountingAlloc};

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

#[test]
fn a_panic_in_the_counted_closure_switches_counting_back_off() {
    let r = std::panic::catch_unwind(|| {
        alloc_count::count(|| {
            let v = std::hint::black_box(vec![1u8; 8]);
            panic!("in the counted closure after allocating {} bytes", v.len());
        })
    });
    assert!(r.is_err());
    let before = alloc_count::counted();
    drop(std::hint::black_box(vec![0u8; 32]));
    assert_eq!(
        alloc_count::counted(),
        before,
        "counting is off again after the panic"
    );
    // And it still counts what a closure allocates.
    let (_, counts) = alloc_count::count(|| drop(std::hint::black_box(vec![0u8; 16])));
    assert_eq!((counts.allocations, counts.bytes), (1, 16));
}

#[test]
fn nested_counts_leave_counting_on_for_the_outer_one() {
    let ((), outer) = alloc_count::count(|| {
        let ((), inner) = alloc_count::count(|| drop(std::hint::black_box(vec![0u8; 4])));
        assert_eq!(inner.allocations, 1);
        drop(std::hint::black_box(vec![0u8; 4]));
    });
    assert_eq!(outer.allocations, 2);
}
