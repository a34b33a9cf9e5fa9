//! Scenario tests of VELOCITY_CONTROL on the whole simulated robot in virtual time: the ramp
//! seen in the simulation's truth, the timeout, a joint driven into its limit, the refusals,
//! `hold` and a gone owner.

use super::super::tests::Robot;
use super::ramp_limits;
use mcm_shared::command::{Axis, Request, SetVelocities, VelocityControl};
use mcm_shared::mode::Mode;
use mcm_shared::ranges::{Arg, ArgRefusal};
use mcm_shared::reply::{Done, Reason};

mod cartesian;

fn velocity_control(timeout_s: Option<f64>) -> Request {
    Request::VelocityControl(VelocityControl { timeout_s })
}

fn set_velocities(velocities_deg_s: [f64; 6]) -> Request {
    Request::SetVelocities(SetVelocities { velocities_deg_s })
}

#[test]
fn two_axes_ramp_within_the_acceleration_limit_to_their_targets() {
    let mut r = Robot::calibrated();
    assert_eq!(r.ok(velocity_control(None), 5), Done::Ack);
    assert_eq!(r.mode(), Mode::VelocityControl);
    r.ok(set_velocities([20.0, 0.0, -30.0, 0.0, 0.0, 0.0]), 5);
    let mut prev = r.cycle.state().sim_true_velocity;
    let mut worst_acc: f64 = 0.0;
    for _ in 0..200 {
        r.step(&[]);
        let v = r.cycle.state().sim_true_velocity;
        for i in [0, 2] {
            worst_acc = worst_acc.max(((v[i] - prev[i]) / 0.005).abs());
        }
        prev = v;
    }
    let v = r.cycle.state().sim_true_velocity;
    assert!(
        (v[0] - 20.0).abs() < 0.5 && (v[2] + 30.0).abs() < 0.5,
        "{v:?}"
    );
    assert!(
        v[1].abs() < 0.5 && v[3].abs() < 0.5,
        "the others keep still: {v:?}"
    );
    // 180 deg/s^2, with the simulated drives' tracking on top.
    assert!(
        worst_acc < 180.0 * 1.3,
        "true acceleration {worst_acc} deg/s^2"
    );
    assert_eq!(r.cycle.state().last_error.seq, 0, "no trip");
}

#[test]
fn the_timeout_stops_to_hold_and_hold_ends_the_mode() {
    let mut r = Robot::calibrated();
    r.ok(velocity_control(Some(0.2)), 5);
    r.ok(set_velocities([0.0, 0.0, 0.0, 0.0, 30.0, 0.0]), 5);
    let entered = r.k;
    r.run_until("HOLD after the timeout", 200, |r| r.mode() == Mode::Hold);
    let cycles = r.k - entered;
    assert!(
        (40..=43).contains(&cycles),
        "HOLD {cycles} cycles after the last set_velocities"
    );
    r.run_until("at rest", 400, Robot::at_rest);
    assert_eq!(
        r.cycle.state().last_error.seq,
        0,
        "a controlled stop, no trip"
    );

    r.ok(velocity_control(None), 5);
    r.ok(set_velocities([0.0, 10.0, 0.0, 0.0, 0.0, 0.0]), 5);
    r.run(50);
    r.ok(Request::Hold, 5);
    assert_eq!(r.mode(), Mode::Hold);
    r.run_until("at rest after hold", 400, Robot::at_rest);
}

#[test]
fn a_joint_driven_into_its_limit_stops_before_it_without_a_trip() {
    let mut r = Robot::calibrated();
    r.ok(velocity_control(None), 5);
    // Axis 2 (limit 120 deg) at full speed, refreshed like a client would.
    for _ in 0..1200 {
        r.ok(set_velocities([0.0, 90.0, 0.0, 0.0, 0.0, 0.0]), 5);
        assert_eq!(
            r.mode(),
            Mode::VelocityControl,
            "{:?}",
            r.cycle.state().last_error
        );
    }
    let s = r.cycle.state();
    let stop = {
        let c = r.cycle.controller();
        ramp_limits(&c.p, &c.safety, 1).stop_max.to_degrees()
    };
    assert!(
        s.sim_true_velocity[1].abs() < 0.05,
        "at rest: {:?}",
        s.sim_true_velocity
    );
    assert!(
        s.sim_true_position[1] < 119.0 && s.sim_true_position[1] > stop - 0.2,
        "stopped at {} deg, before 120 - 1 deg margin",
        s.sim_true_position[1]
    );
    assert_eq!(s.last_error.seq, 0, "no trip");
    // Away from the limit is allowed at once.
    r.ok(set_velocities([0.0, -10.0, 0.0, 0.0, 0.0, 0.0]), 5);
    r.run(100);
    assert!(r.cycle.state().sim_true_velocity[1] < -5.0);
}

#[test]
fn refusals_name_mode_axis_value_and_range() {
    let mut r = Robot::calibrated();
    assert_eq!(
        r.refused(set_velocities([0.0; 6]), 5),
        Reason::WrongMode { mode: Mode::Hold }
    );
    r.ok(velocity_control(None), 5);
    assert_eq!(
        r.refused(velocity_control(None), 5),
        Reason::WrongMode {
            mode: Mode::VelocityControl
        }
    );
    let reason = r.refused(set_velocities([0.0, 0.0, 0.0, 151.0, 0.0, 0.0]), 5);
    assert_eq!(
        reason,
        Reason::InvalidArgument {
            refusal: ArgRefusal {
                arg: Arg::Velocities,
                axis: Axis::new(4),
                value: 151.0,
                min: -150.0,
                max: 150.0
            }
        }
    );
    // The words of the gateway's refusal of the same value (one table of ranges).
    assert_eq!(
        reason.to_string(),
        "argument \"velocities[3]\" = 151 is not allowed; expected a number from -150 to 150 \
         deg/s (the axis's maximum velocity)"
    );
    // The full limit itself is allowed.
    r.ok(set_velocities([-90.0, 0.0, 0.0, 150.0, 0.0, 0.0]), 5);
    r.ok(Request::Hold, 5);
}

#[test]
fn a_gone_owner_ends_velocity_control_with_a_controlled_stop() {
    let mut r = Robot::calibrated();
    // The calibration made client 42 the owner.
    r.command_from(42, velocity_control(None), 5);
    assert_eq!(r.mode(), Mode::VelocityControl);
    let refused = r.command_from(8, set_velocities([1.0; 6]), 5);
    assert!(
        matches!(
            refused.outcome,
            mcm_shared::reply::Outcome::Refused(Reason::NotOwner { owner: 42 })
        ),
        "{refused:?}"
    );
    r.command_from(42, set_velocities([0.0, 0.0, 20.0, 0.0, 0.0, 0.0]), 5);
    r.run(100);
    r.command_from(42, Request::ClientGone, 5);
    assert_eq!(r.mode(), Mode::Hold);
    r.run_until("at rest", 400, Robot::at_rest);
}
