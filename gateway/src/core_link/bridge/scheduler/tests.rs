use super::*;

/// A job of `n` samples, named for the test.
#[derive(Debug, PartialEq)]
struct J {
    name: &'static str,
    left: usize,
}

fn j(name: &'static str, left: usize) -> J {
    J { name, left }
}

/// Publish while allowed; the names of the jobs whose samples went out, in order.
fn run(s: &mut Scheduler<J>, max: usize) -> Vec<&'static str> {
    let mut out = Vec::new();
    while out.len() < max {
        let Some(g) = s.next() else { break };
        let job = s.job(g).expect("granted job exists");
        job.left -= 1;
        out.push(job.name);
        let done = job.left == 0;
        s.sent(g);
        if done {
            s.finish(g);
        }
    }
    out
}

#[test]
fn connections_take_turns_sample_by_sample() {
    let mut s = Scheduler::default();
    s.push(1, j("a", 3), false);
    s.push(2, j("b", 2), false);
    s.push(3, j("c", 1), false);
    assert_eq!(run(&mut s, 100), ["a", "b", "c", "a", "b", "a"]);
    assert!(s.is_empty());
    assert_eq!(s.in_flight(), 6);
}

#[test]
fn a_connection_is_capped_and_the_others_go_on() {
    let mut s = Scheduler::default();
    s.push(1, j("flood", 250), false);
    let out = run(&mut s, 100);
    assert_eq!(out.len(), PER_CLIENT_IN_FLIGHT, "{out:?}");
    s.push(2, j("other", 1), false);
    assert_eq!(run(&mut s, 100), ["other"]);
    // One answer to the flood lets exactly one more of its samples out.
    s.answered(1, false);
    assert_eq!(run(&mut s, 100), ["flood"]);
    assert_eq!(run(&mut s, 100), Vec::<&str>::new());
}

#[test]
fn all_connections_together_are_capped_below_the_core_buffer() {
    let mut s = Scheduler::default();
    for c in 0..40 {
        s.push(c, j("flood", 250), false);
    }
    let out = run(&mut s, 1000);
    assert_eq!(out.len(), ORDINARY_IN_FLIGHT);
    assert_eq!(s.in_flight(), ORDINARY_IN_FLIGHT);
}

#[test]
fn hold_jumps_the_queue_even_when_ordinary_room_is_used_up() {
    let mut s = Scheduler::default();
    for c in 0..40 {
        s.push(c, j("flood", 250), false);
    }
    run(&mut s, 1000);
    s.push(99, j("hold", 1), true);
    s.push(98, j("client_gone", 1), true);
    assert_eq!(run(&mut s, 1000), ["hold", "client_gone"]);
    // Urgent samples fill the reserve, never beyond it.
    for _ in 0..100 {
        s.push(97, j("hold", 1), true);
    }
    let out = run(&mut s, 1000);
    assert_eq!(out.len(), ALL_IN_FLIGHT - ORDINARY_IN_FLIGHT - 2);
    assert_eq!(s.in_flight(), ALL_IN_FLIGHT);
    assert!(s.in_flight() < COMMAND_BUFFER);
    // An answer frees a place; the urgent queue still goes first.
    s.answered(1, false);
    assert_eq!(run(&mut s, 1), ["hold"]);
}

#[test]
fn hold_goes_before_queued_work_of_every_connection() {
    let mut s = Scheduler::default();
    s.push(1, j("a", 5), false);
    s.push(2, j("b", 5), false);
    assert_eq!(run(&mut s, 2), ["a", "b"]);
    s.push(3, j("hold", 1), true);
    assert_eq!(run(&mut s, 3), ["hold", "a", "b"]);
}

#[test]
fn drain_returns_everything_and_forgets_what_was_in_flight() {
    let mut s = Scheduler::default();
    s.push(1, j("a", 100), false);
    s.push(1, j("a2", 1), false);
    s.push(2, j("hold", 1), true);
    run(&mut s, 3);
    let left: Vec<_> = s.drain().into_iter().map(|j| j.name).collect();
    assert_eq!(left, ["a", "a2"]);
    assert!(s.is_empty());
    assert_eq!(s.in_flight(), 0);
    assert_eq!(s.next(), None);
}
