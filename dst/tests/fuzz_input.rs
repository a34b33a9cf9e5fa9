//! The fuzz target's scripted runs (`mcm_dst::fuzz_input`), run here in CI where the fuzz
//! target itself is not: a script drives the arm through its modes without a false alarm,
//! sends a client's commands one a cycle, and stops at its cycle limit.

use mcm_dst::fuzz_input::{Limits, Script, Step, run_script};
use mcm_dst::rng::Rng;
use mcm_dst::run::config;
use mcm_dst::stamp::calibrate_all;
use mcm_shared::alloc_count::CountingAlloc;
use mcm_shared::command::{Axis, Request, SimCommand};
use mcm_shared::mode::Mode;

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

const LIMITS: Limits = Limits {
    max_cycles: 20_000,
    cpu_budget: false,
};

fn step(cycles: u32, commands: &[(usize, Request)]) -> Step {
    Step {
        cycles,
        commands: commands.iter().map(|(c, r)| (*c, r.encode())).collect(),
        bus: None,
    }
}

fn script(steps: Vec<Step>) -> Script {
    Script {
        cfg: config(&mut Rng::new(7)),
        bus_seed: 7,
        steps,
    }
}

#[test]
fn a_script_calibrates_and_survives_faults_without_a_false_alarm() {
    let block = SimCommand {
        block_axis: Axis::new(2),
        ..SimCommand::default()
    };
    let unblock = SimCommand {
        unblock_axis: Axis::new(2),
        ..SimCommand::default()
    };
    let s = script(vec![
        step(600, &[(0, Request::TakeControl), (0, Request::Hold)]),
        step(8000, &[(0, calibrate_all())]),
        step(200, &[(1, Request::Sim(block)), (0, Request::Hold)]),
        step(
            200,
            &[(1, Request::Sim(unblock)), (2, Request::ReleaseControl)],
        ),
        step(
            600,
            &[
                (0, Request::ClientGone),
                (0, Request::TakeControl),
                (0, Request::Hold),
            ],
        ),
    ]);
    let r = run_script(&s, LIMITS).unwrap_or_else(|v| panic!("{v}"));
    assert!(r.modes_reached[Mode::Hold as usize] > 0, "{r:?}");
    assert!(r.modes_reached[Mode::Calibration as usize] > 0, "{r:?}");
    // take_control, hold, calibrate, sim, hold, sim, take_control, hold (client_gone's
    // answer: OK as well); release_control of a client without control refused.
    assert!(r.answers[0] >= 8, "{r:?}");
    assert!(r.answers[1] >= 1, "{r:?}");
}

#[test]
fn a_client_sends_one_command_a_cycle_and_the_step_lengthens_for_them() {
    let many: Vec<(usize, Request)> = (0..30).map(|_| (1, Request::Status)).collect();
    let r = run_script(&script(vec![step(1, &many)]), LIMITS).unwrap_or_else(|v| panic!("{v}"));
    assert!(r.cycles >= 30, "{r:?}");
    assert_eq!(r.answers[0], 30, "{r:?}");
}

#[test]
fn a_script_stops_at_its_cycle_limit() {
    let limits = Limits {
        max_cycles: 50,
        ..LIMITS
    };
    let r = run_script(&script(vec![step(200, &[]); 3]), limits).unwrap_or_else(|v| panic!("{v}"));
    assert_eq!(r.cycles, 50);
}
