use super::*;

#[test]
fn a_failed_drain_is_counted_and_keeps_what_came_before() {
    let mut errors = 0;
    let mut intake = Intake::with_capacity(8);
    received(
        Drained {
            count: 3,
            error: None,
        },
        &mut intake,
        &mut errors,
    );
    assert_eq!((intake.waiting(), errors), (3, 0));
    let failed = crate::ipc::ReceiveError(iceoryx2::port::ReceiveError::ExceedsMaxBorrows);
    for count in [2, 0] {
        let error = Some(failed);
        received(Drained { count, error }, &mut intake, &mut errors);
    }
    assert_eq!((intake.waiting(), errors), (5, 2));
}

#[test]
fn missed_deadlines_are_counted_and_the_schedule_restarts() {
    // Period 10: a cycle due at 10 that ends at 12 is on time; next deadline 20.
    assert_eq!(next_deadline(10, 12, 10), (20, 0));
    // Ending exactly on the next deadline is still on time.
    assert_eq!(next_deadline(10, 20, 10), (20, 0));
    // Due at 20, ended at 47: deadlines 30 and 40 missed, the schedule goes on at 50.
    assert_eq!(next_deadline(20, 47, 10), (50, 2));
    // Ended at 31, just after deadline 30: one missed, next at 40.
    assert_eq!(next_deadline(20, 31, 10), (40, 1));
}
