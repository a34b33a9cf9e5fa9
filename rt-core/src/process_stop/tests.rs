use super::*;
use crate::sim_edge::SimCycle;
use mcm_shared::config::RobotConfig;
use mcm_sim::SimBus;

const MS: u64 = 1_000_000;

fn robot() -> SimCycle {
    let cfg = RobotConfig::prob2_default();
    SimCycle::new(&cfg, SimBus::new(&cfg)).unwrap()
}

#[test]
fn the_first_signal_starts_the_shutdown_and_a_late_second_one_ends_it() {
    let mut r = robot();
    let c = r.controller_mut();
    let mut stop = StopSequence::new(3);
    assert_eq!(stop.poll(c, 3, 0), None);
    assert!(
        c.shutdown_status().is_none(),
        "signals before the loop do not count"
    );
    assert_eq!(stop.poll(c, 4, 1000 * MS), None);
    assert!(stop.stopping());
    assert_eq!(c.shutdown_status().unwrap().phase, ShutdownPhase::Requested);
    // Within the debounce: the same request (a process group and its supervisor).
    assert_eq!(stop.poll(c, 5, 1100 * MS), None);
    let ended = stop.poll(c, 6, 1000 * MS + SECOND_SIGNAL_DEBOUNCE_NS);
    assert_eq!(
        ended,
        Some(StopOutcome::Interrupted {
            phase: ShutdownPhase::Requested,
            after_ns: SECOND_SIGNAL_DEBOUNCE_NS,
        })
    );
    assert!(ended.unwrap().to_string().contains("second stop signal"));
}

#[test]
fn past_the_wall_clock_bound_the_drives_are_disabled_regardless() {
    let mut r = robot();
    let c = r.controller_mut();
    let mut stop = StopSequence::new(0);
    stop.poll(c, 1, 0);
    let late = c.shutdown_bound_ns() + WALL_ALLOWANCE_NS + 1;
    assert_eq!(
        stop.poll(c, 1, late),
        None,
        "one more cycle sends the disable"
    );
    assert_eq!(
        stop.poll(c, 1, late + 5 * MS),
        None,
        "the final state is published"
    );
    let end = late + 5 * MS + FINAL_STATE_NS;
    let Some(StopOutcome::Finished {
        result, took_ns, ..
    }) = stop.poll(c, 1, end)
    else {
        panic!("finished after the bound");
    };
    assert_eq!(
        took_ns,
        late + 5 * MS,
        "the time it took, not the final publishing"
    );
    assert!(
        matches!(result, ShutdownResult::TimedOut { .. }),
        "{result:?}"
    );
}
