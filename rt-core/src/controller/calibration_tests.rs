//! Scenario tests of calibration in virtual time: every group and direction finds the true
//! angles again and again (another axis hitting its stop is no contact), an aborted or failed
//! re-calibration keeps the previous calibration, and a reference that disagrees with the
//! previous calibration fails with its figures.

use super::tests::Robot;
use mcm_shared::command::{Axis, Calibrate, Direction, Request, Which};
use mcm_shared::mode::Mode;
use mcm_shared::reply::{CalibrationFailure, Outcome, Reason};

fn calibrate(which: Which, elbow: Direction, wrist: Direction) -> Request {
    Request::Calibrate(Calibrate {
        which,
        elbow_direction: elbow,
        wrist_direction: wrist,
        force_mechanical_stop: false,
    })
}

/// Reported minus true position per axis [deg], once the arm has settled.
fn errors(r: &mut Robot) -> [f64; 6] {
    r.run(40);
    let (m, t) = (r.measured(), r.truth());
    core::array::from_fn(|i| m[i] - t[i])
}

fn assert_true(r: &mut Robot, what: &str) {
    let e = errors(r);
    assert!(
        e.iter().all(|x| x.abs() < 0.05),
        "{what}: reported minus true {e:?}"
    );
}

#[test]
fn every_group_and_direction_finds_the_true_angles_again_and_again() {
    use Direction::{Negative as N, Positive as P};
    let mut r = Robot::new();
    r.calibrate_all();
    assert_true(&mut r, "ALL");
    let runs = [
        (Which::Elbow, P, P),
        (Which::Elbow, P, P),
        (Which::Elbow, P, P),
        (Which::All, P, N),
        (Which::All, N, P),
        (Which::Wrist, P, N),
        (Which::Elbow, N, P),
        (Which::Axis(Axis::new(2).unwrap()), P, P),
        (Which::Axis(Axis::new(5).unwrap()), P, N),
        (Which::All, P, P),
    ];
    for (n, (which, elbow, wrist)) in runs.into_iter().enumerate() {
        // Start each from a slightly different pose and phase.
        r.run(n as u64 * 7);
        let resp = r.command(calibrate(which, elbow, wrist), 20_000);
        assert!(
            matches!(resp.outcome, Outcome::Done(_)),
            "run {n} {which:?}: {resp:?}"
        );
        assert_true(
            &mut r,
            &format!("run {n} {which:?} elbow {elbow:?} wrist {wrist:?}"),
        );
    }
}
