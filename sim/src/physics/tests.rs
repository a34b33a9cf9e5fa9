//! Scenario tests of the simulated arm ([`crate::physics::ArmSim`]). Test-only module.

use crate::physics::ArmSim;
use mcm_dynamics::ArmModel;
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;

const N: usize = NUM_AXES;
const DT: f64 = 500e-6;
/// Steps in 5 s of simulated time at 500 µs.
const FIVE_SECONDS: usize = 10_000;

/// The P-Rob2 configuration with every brake removed: these tests are about the bare physics
/// (each brake test adds its brake itself).
fn unbraked() -> RobotConfig {
    let mut cfg = RobotConfig::prob2_default();
    for a in &mut cfg.axes {
        a.brake = false;
    }
    cfg
}

fn sim_with(cfg: &RobotConfig) -> ArmSim {
    ArmSim::new(ArmModel::from_config(cfg), cfg)
}

fn sim() -> ArmSim {
    sim_with(&unbraked())
}

fn deg(v: [f64; N]) -> [f64; N] {
    v.map(f64::to_radians)
}

fn max_abs_diff(a: &[f64; N], b: &[f64; N]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn starts_at_the_configured_position_at_rest() {
    let mut cfg = unbraked();
    cfg.sim.initial_position_deg = [10.0, -20.0, 30.0, 0.0, 45.0, 0.0];
    let s = sim_with(&cfg);
    assert_eq!(s.position(), deg([10.0, -20.0, 30.0, 0.0, 45.0, 0.0]));
    assert_eq!(s.velocity(), [0.0; N]);
}

#[test]
fn stops_lie_symmetrically_beyond_the_limits() {
    let s = sim();
    let expect: [f64; N] = [175.0, 125.0, 140.0, 175.0, 125.0, 175.0];
    for (i, e) in expect.iter().enumerate() {
        let (lo, hi) = s.mechanical_stops(i);
        assert!(
            (lo + e.to_radians()).abs() < 1e-12 && (hi - e.to_radians()).abs() < 1e-12,
            "axis {i}: {lo} {hi}"
        );
    }
    assert_eq!(s.mechanical_stops(6), (f64::NEG_INFINITY, f64::INFINITY));
}

/// Deepest penetration beyond any stop [rad].
fn penetration(s: &ArmSim) -> f64 {
    let q = s.position();
    (0..N)
        .map(|i| {
            let (lo, hi) = s.mechanical_stops(i);
            (lo - q[i]).max(q[i] - hi).max(0.0)
        })
        .fold(0.0, f64::max)
}

#[test]
fn unpowered_arm_falls_onto_its_stop_and_rests_there() {
    let mut s = sim();
    s.set_state(deg([0.0, 30.0, 0.0, 0.0, 0.0, 0.0]), [0.0; N]);
    let mut deepest: f64 = 0.0;
    for _ in 0..12_000 {
        s.step(&[0.0; N], DT);
        deepest = deepest.max(penetration(&s));
    }
    let q = s.position();
    let (_, hi) = s.mechanical_stops(1);
    // J2 rests on its upper stop; the static penetration under the arm's weight is about
    // 35 Nm / 20000 Nm/rad = 0.1 deg.
    assert!(
        (q[1] - hi).abs() < 0.5f64.to_radians(),
        "J2 at {} deg",
        q[1].to_degrees()
    );
    // Measured: 1.07 deg at the impact (frictionless: 1.33 deg, see the energy test).
    assert!(
        deepest < 2f64.to_radians(),
        "penetration {} deg",
        deepest.to_degrees()
    );
    assert_eq!(
        s.velocity(),
        [0.0; N],
        "at rest, held by stop and static friction"
    );
    eprintln!(
        "fall: deepest penetration {:.3} deg, final q {:?} deg",
        deepest.to_degrees(),
        q.map(|x| (x.to_degrees() * 100.0).round() / 100.0)
    );
}

#[test]
fn arm_held_by_its_gravity_torques_stays_still() {
    // Frictionless, so only the exactness of the model holds the arm (with friction the arm
    // would stick anyway; see torque_below_the_coulomb_level_does_not_creep).
    let q0 = deg([10.0, 30.0, -40.0, 15.0, 20.0, 0.0]);
    let mut s = sim();
    s.set_friction_enabled(false);
    s.set_state(q0, [0.0; N]);
    let hold = s.model().gravity_torques(&q0);
    assert!(hold[1].abs() > 10.0, "the pose must load the arm: {hold:?}");
    for _ in 0..FIVE_SECONDS {
        s.step(&hold, DT);
    }
    let drift = max_abs_diff(&s.position(), &q0);
    assert!(drift < 1e-9, "drift {drift} rad");
}

#[test]
fn torque_below_the_coulomb_level_does_not_creep() {
    let q0 = deg([0.0, 30.0, -20.0, 0.0, 30.0, 0.0]);
    let mut s = sim();
    s.set_state(q0, [0.0; N]);
    let mut tau = s.model().gravity_torques(&q0);
    let fc = s.model().friction().map(|f| f.coulomb);
    for i in 0..N {
        // 95 % of the Coulomb level, alternating directions, on every axis at once.
        tau[i] += if i % 2 == 0 { 0.95 } else { -0.95 } * fc[i];
    }
    for _ in 0..FIVE_SECONDS {
        s.step(&tau, DT);
    }
    assert_eq!(s.position(), q0, "no creep at all");
    // Just above the level, the joint breaks away.
    tau[0] += 0.1 * fc[0];
    for _ in 0..1000 {
        s.step(&tau, DT);
    }
    assert!(
        s.position()[0] > q0[0] + 1e-4,
        "J1 breaks away above the Coulomb level"
    );
}

/// Frictionless motion for 5 s from `q0`, `qd0`: (initial energy [J], largest growth of
/// `energy()` [J], final energy change [J], deepest penetration into a stop [rad]).
fn free_swing(cfg: &RobotConfig, q0: [f64; N], qd0: [f64; N], dt: f64) -> (f64, f64, f64, f64) {
    let mut s = sim_with(cfg);
    s.set_friction_enabled(false);
    s.set_state(q0, qd0);
    let e0 = s.energy();
    let mut growth: f64 = 0.0;
    let mut deepest: f64 = 0.0;
    for _ in 0..(5.0 / dt).round() as usize {
        s.step(&[0.0; N], dt);
        growth = growth.max(s.energy() - e0);
        deepest = deepest.max(penetration(&s));
    }
    (e0, growth, s.energy() - e0, deepest)
}

#[test]
fn energy_does_not_grow_in_a_frictionless_free_swing() {
    // Ceiling-mounted arm (gravity +z): q = 0 hangs down and the arm swings about it, every
    // axis moving, the base turning (Coriolis terms). The stops are moved out of the way (the
    // free wrist roll turns several times).
    let mut cfg = unbraked();
    cfg.arm.gravity = [0.0, 0.0, 9.81];
    for a in &mut cfg.axes {
        (a.min_deg, a.max_deg) = (-3600.0, 3600.0);
        a.calibration.stop_deg = 3605.0 * f64::from(a.calibration.direction);
    }
    let q0 = deg([0.0, 40.0, -30.0, 20.0, 50.0, 0.0]);
    let qd0 = [0.5, 0.0, 0.5, 0.0, 0.0, 1.0];
    let (e0, growth, change, deepest) = free_swing(&cfg, q0, qd0, DT);
    assert_eq!(deepest, 0.0, "the swing must stay clear of the stops");
    eprintln!(
        "ceiling swing, dt 500 us: E0 = {e0:.3} J, max growth {growth:.3e} J, \
         change after 5 s {change:.3e} J"
    );
    // Measured: growth 0 J, change -0.23 J (peak kinetic energy 12.8 J); at dt = 250 us
    // -0.12 J, at 125 us -0.06 J: the first-order error of the semi-implicit Euler step.
    assert!(growth < 1e-3, "energy grew by {growth} J");
    assert!(change.abs() < 0.5, "energy changed by {change} J");

    // Floor-mounted arm falling from J2 = 30 deg onto its stops: the stops' dampers and the
    // implicit springs may only remove energy. Measured: growth 0 J, -87.6 J after 5 s,
    // deepest penetration 1.33 deg.
    let q0 = deg([0.0, 30.0, 0.0, 0.0, 10.0, 0.0]);
    let (e0, growth, change, deepest) = free_swing(&unbraked(), q0, [0.0; N], DT);
    eprintln!(
        "fall onto the stops: E0 = {e0:.3} J, max growth {growth:.3e} J, change {change:.3e} J, \
         penetration {:.2} deg",
        deepest.to_degrees()
    );
    assert!(
        deepest > 0.0 && deepest < 3f64.to_radians(),
        "penetration {deepest} rad"
    );
    assert!(growth < 1e-3, "energy grew by {growth} J");
}

#[test]
fn blocked_axis_does_not_move_under_large_torques() {
    let q0 = deg([0.0, 30.0, -20.0, 0.0, 30.0, 0.0]);
    let mut s = sim();
    s.set_state(q0, [0.0; N]);
    s.set_blocked(0, true);
    s.set_blocked(3, true);
    s.set_blocked(0, true); // keeps the first anchor
    assert!(s.is_blocked(0) && !s.is_blocked(1));
    let mut tau = s.model().gravity_torques(&q0);
    tau[0] += 200.0;
    tau[3] -= 40.0;
    let k = unbraked().sim.stop_stiffness_nm_rad;
    let mut worst = [0.0f64; N];
    for _ in 0..2000 {
        s.step(&tau, DT);
        for (w, (q, q0)) in worst.iter_mut().zip(s.position().iter().zip(&q0)) {
            *w = w.max((q - q0).abs());
        }
    }
    // Only the spring deflection of the obstacle, (torque - Coulomb) / k, without overshoot
    // beyond 10 %.
    assert!(worst[0] < 1.1 * 200.0 / k, "J1 moved {} rad", worst[0]);
    assert!(worst[3] < 1.1 * 40.0 / k, "J4 moved {} rad", worst[3]);
    assert!(s.velocity()[0].abs() < 1e-6 && s.velocity()[3].abs() < 1e-6);
    // Unblocked, the same torque turns the axis.
    s.set_blocked(0, false);
    for _ in 0..200 {
        s.step(&tau, DT);
    }
    assert!(s.position()[0] > q0[0] + 0.01, "J1 moves once free");
}

#[test]
fn external_torques_accelerate_the_arm_in_their_direction() {
    let q0 = deg([0.0, 20.0, 10.0, 0.0, 0.0, 0.0]);
    let mut s = sim();
    s.set_state(q0, [0.0; N]);
    let hold = s.model().gravity_torques(&q0);
    s.set_external_torques([20.0, 0.0, -15.0, 0.0, 0.0, -5.0]);
    for _ in 0..200 {
        s.step(&hold, DT);
    }
    let (q, v) = (s.position(), s.velocity());
    assert!(q[0] > q0[0] && v[0] > 0.0, "J1: {} {}", q[0], v[0]);
    assert!(q[2] < q0[2] && v[2] < 0.0, "J3: {} {}", q[2], v[2]);
    assert!(q[5] < q0[5] && v[5] < 0.0, "J6: {} {}", q[5], v[5]);
    assert_eq!(s.external_torques()[0], 20.0);
}

#[test]
fn engaged_brake_holds_up_to_twice_the_peak_torque() {
    let mut cfg = unbraked();
    cfg.axes[1].brake = true;
    let mut s = sim_with(&cfg);
    // 2 x 10 A x 0.12 Nm/A x 120 x 0.9
    assert!((s.brake_holding_torque(1) - 259.2).abs() < 1e-9);
    assert!(
        s.brake_engaged(1),
        "spring-applied brake is engaged at power-up"
    );
    s.set_brake(0, true); // axis without brake: no effect
    assert!(!s.brake_engaged(0));
    let q0 = deg([0.0, 60.0, -60.0, 0.0, 0.0, 0.0]);
    s.set_state(q0, [0.0; N]);
    // Hold J3 with its motor, J2 with its brake only (gravity ~ 45 Nm).
    let mut tau = s.model().gravity_torques(&q0);
    tau[1] = 0.0;
    for _ in 0..2000 {
        s.step(&tau, DT);
    }
    assert_eq!(s.position(), q0);
    // Overload above 259 Nm: the brake slips.
    s.set_external_torques([0.0, 300.0, 0.0, 0.0, 0.0, 0.0]);
    for _ in 0..200 {
        s.step(&tau, DT);
    }
    assert!(s.position()[1] > q0[1] + 1e-3, "slipping brake");
    // Released, gravity takes the arm.
    s.set_external_torques([0.0; N]);
    s.set_brake(1, false);
    let before = s.position()[1];
    for _ in 0..400 {
        s.step(&tau, DT);
    }
    assert!(s.position()[1] > before + 0.01, "falls once released");
}

#[test]
fn arm_driven_into_a_stop_rests_at_the_spring_deflection() {
    let mut s = sim();
    s.set_state(deg([170.0, 0.0, 0.0, 0.0, 0.0, 0.0]), [0.0; N]);
    let tau = [60.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    for _ in 0..4000 {
        s.step(&tau, DT);
    }
    let (_, hi) = s.mechanical_stops(0);
    let k = unbraked().sim.stop_stiffness_nm_rad;
    // Rests where the spring carries the torque, give or take what static friction (3 Nm on
    // J1) holds in either direction.
    let pen = s.position()[0] - hi;
    assert!(
        pen > (60.0 - 3.1) / k && pen < (60.0 + 3.1) / k,
        "penetration {pen} rad"
    );
    assert!(s.velocity()[0].abs() < 1e-9, "at rest: {}", s.velocity()[0]);
}

#[test]
fn results_are_a_pure_function_of_the_inputs() {
    let run = || {
        let mut s = sim();
        s.set_state(
            deg([5.0, 35.0, -10.0, 3.0, 20.0, -7.0]),
            [0.2, 0.0, 0.0, 0.5, 0.0, 0.0],
        );
        for n in 0..3000 {
            let t = n as f64 * DT;
            s.step(&[10.0 * t.sin(), -30.0, 5.0, 1.0, -2.0 * t.cos(), 0.3], DT);
        }
        (s.position(), s.velocity())
    };
    let (a, b) = (run(), run());
    assert_eq!(a.0.map(f64::to_bits), b.0.map(f64::to_bits));
    assert_eq!(a.1.map(f64::to_bits), b.1.map(f64::to_bits));
}

#[test]
fn bad_inputs_leave_a_finite_state() {
    let mut s = sim();
    s.set_state(deg([0.0, 30.0, 0.0, 0.0, 0.0, 0.0]), [0.0; N]);
    let before = (s.position(), s.velocity());
    s.step(&[0.0; N], f64::NAN);
    s.step(&[0.0; N], -1.0);
    assert_eq!(
        (s.position(), s.velocity()),
        before,
        "invalid dt does nothing"
    );
    s.step(&[f64::NAN, f64::INFINITY, 0.0, 0.0, 0.0, 0.0], DT);
    s.set_external_torques([f64::NAN; N]);
    s.set_state([f64::NAN; N], [0.0; N]);
    s.set_blocked(17, true);
    s.set_brake(17, true);
    for _ in 0..100 {
        s.step(&[1e6; N], 0.1); // a huge step with huge torques: stable, finite
    }
    assert!(
        s.position()
            .iter()
            .chain(&s.velocity())
            .all(|v| v.is_finite())
    );
    assert!(s.energy().is_finite());
}
