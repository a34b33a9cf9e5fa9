//! Moves received during motion, against the simulated robot in virtual time: re-planned from
//! the commanded state, per axis, with no step in the commanded velocity.

use crate::controller::tests::Robot;
use mcm_shared::command::{Axis, MoveAll, MoveAxis, Pvt, Request};
use mcm_shared::mode::Mode;
use mcm_shared::reply::{Done, Reason};

const PVT: Request = Request::Pvt(Pvt { dt_s: 0.01 });
/// Axes 1-3 [deg/s²]; 4-6 have more.
const MAX_ACCELERATION: [f64; 6] = [180.0, 180.0, 180.0, 300.0, 300.0, 300.0];

fn move_axis(axis: u8, target_deg: f64, velocity_factor: f64) -> Request {
    Request::MoveAxis(MoveAxis {
        axis: Axis::new(axis).unwrap(),
        target_deg,
        velocity_factor,
    })
}

fn move_all(targets_deg: [f64; 6], velocity_factor: f64) -> Request {
    Request::MoveAll(MoveAll {
        targets_deg,
        velocity_factor,
    })
}

fn in_pvt() -> Robot {
    let mut r = Robot::new();
    r.calibrate_all();
    r.ok(PVT, 10);
    r
}

/// Run until the commanded motion ends, checking every cycle that the commanded velocity
/// changes by no more than the acceleration limit allows in one period.
fn run_to_rest(r: &mut Robot, max_cycles: u64) {
    let mut prev = r.cycle.state().velocity;
    for _ in 0..max_cycles {
        r.step(&[]);
        let v = r.cycle.state().velocity;
        check_step(&prev, &v);
        prev = v;
        if !r.cycle.controller().state.planned_motion() {
            return;
        }
    }
    panic!("still moving after {max_cycles} cycles");
}

fn check_step(prev: &[f64; 6], v: &[f64; 6]) {
    for i in 0..6 {
        let dv = (v[i] - prev[i]).abs();
        assert!(
            dv <= MAX_ACCELERATION[i] * 0.005 * (1.0 + 1e-9) + 1e-9,
            "axis {}: commanded velocity jumps {dv} deg/s in one cycle ({} -> {})",
            i + 1,
            prev[i],
            v[i]
        );
    }
}

/// Send `req` in the next cycle, checking the velocity step across it.
fn ok_smoothly(r: &mut Robot, req: Request) -> Done {
    let before = r.cycle.state().velocity;
    let done = r.ok(req, 1);
    check_step(&before, &r.cycle.state().velocity);
    done
}

#[test]
fn retargeting_mid_way_arrives_at_the_new_target_without_a_step() {
    let mut r = in_pvt();
    r.ok(move_axis(1, 60.0, 0.8), 10);
    r.run(60);
    assert!(r.cycle.state().velocity[0] > 30.0, "moving fast");
    // Behind the axis: it brakes, turns back and arrives.
    ok_smoothly(&mut r, move_axis(1, -10.0, 0.5));
    run_to_rest(&mut r, 2000);
    assert!((r.cycle.state().commanded_position[0] + 10.0).abs() < 1e-9);
    r.run(100);
    assert!((r.truth()[0] + 10.0).abs() < 0.05, "{:?}", r.truth());
    assert_eq!(r.mode(), Mode::Pvt);
}

#[test]
fn another_axis_starts_alongside_and_both_arrive() {
    let mut r = in_pvt();
    r.ok(move_axis(1, 40.0, 0.5), 10);
    r.run(40);
    let v1 = r.cycle.state().velocity[0];
    ok_smoothly(&mut r, move_axis(3, -20.0, 0.5));
    // Axis 1 carries on (its velocity did not change more than one cycle's worth).
    assert!((r.cycle.state().velocity[0] - v1).abs() <= 0.9 + 1e-9);
    run_to_rest(&mut r, 2000);
    let cmd = r.cycle.state().commanded_position;
    assert!(
        (cmd[0] - 40.0).abs() < 1e-9 && (cmd[2] + 20.0).abs() < 1e-9,
        "{cmd:?}"
    );
    r.run(100);
    let t = r.truth();
    assert!(
        (t[0] - 40.0).abs() < 0.05 && (t[2] + 20.0).abs() < 0.05,
        "{t:?}"
    );
}

#[test]
fn move_all_during_motion_answers_the_new_plan() {
    let mut r = in_pvt();
    r.ok(move_axis(2, 50.0, 1.0), 10);
    r.run(50);
    let target = [10.0, 0.0, 0.0, 20.0, 0.0, 0.0];
    let Done::MoveAll(plan) = ok_smoothly(&mut r, move_all(target, 0.5)) else {
        panic!("move_all answers its plan")
    };
    // Axis 2 moves at speed and must brake and come back: it takes longest.
    assert_eq!(plan.longest, Axis::ALL[1], "{plan:?}");
    assert!(plan.velocities_deg_s[1] >= r.cycle.state().velocity[1].abs() - 1e-6);
    assert!(plan.velocities_deg_s[3] > 0.0 && plan.velocities_deg_s[2] == 0.0);
    let start = r.k;
    run_to_rest(&mut r, 2000);
    let took = (r.k - start) as f64 * 0.005;
    assert!(
        (took - plan.duration_s).abs() <= 0.011,
        "took {took} s, planned {} s",
        plan.duration_s
    );
    let cmd = r.cycle.state().commanded_position;
    assert!((0..6).all(|i| (cmd[i] - target[i]).abs() < 1e-9), "{cmd:?}");
}

#[test]
fn a_move_right_as_the_last_one_arrives_is_accepted() {
    let mut r = in_pvt();
    r.ok(move_axis(1, 5.0, 0.5), 10);
    r.run_until("nearly there", 2000, |r| {
        r.cycle.controller().state.remaining().unwrap_or(0.0) < 0.03
    });
    r.ok(move_axis(1, 6.0, 0.5), 1);
    run_to_rest(&mut r, 2000);
    assert!((r.cycle.state().commanded_position[0] - 6.0).abs() < 1e-9);
}

#[test]
fn a_replan_that_would_overshoot_the_reachable_range_is_refused_and_the_move_carries_on() {
    let mut r = in_pvt();
    // To the end of the reachable range at full speed, re-targeted behind at a low factor:
    // settling at that factor before braking would pass 169 deg.
    r.ok(move_axis(1, 169.0, 1.0), 10);
    r.run_until("close to the target", 3000, |r| {
        r.cycle.state().commanded_position[0] > 150.0
    });
    let reason = r.refused(move_axis(1, 0.0, 0.05), 1);
    if let Reason::Unreachable { target_deg, .. } = reason {
        assert!(target_deg > 169.0, "{reason:?}");
    } else {
        panic!("{reason:?}");
    }
    run_to_rest(&mut r, 3000);
    assert!((r.cycle.state().commanded_position[0] - 169.0).abs() < 1e-9);
}
