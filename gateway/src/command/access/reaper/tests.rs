use super::*;

#[test]
fn only_ids_of_other_dead_processes_are_orphaned() {
    let dead = |_| false;
    let live = |_| true;
    assert!(orphaned((4242 << 32) | 3, 100, dead));
    assert!(!orphaned((4242 << 32) | 3, 100, live), "its process lives");
    assert!(!orphaned((100 << 32) | 3, 100, dead), "one of ours");
    assert!(!orphaned(42, 100, dead), "names no process");
    assert!(!orphaned(0, 100, dead), "nobody");
    assert!(process_alive(std::process::id()));
}
