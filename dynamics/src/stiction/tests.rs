use super::*;

fn coupled_w() -> Matrix6<f64> {
    let mut w = Matrix6::identity() * 2.0;
    w[(0, 1)] = 0.8;
    w[(1, 0)] = 0.8;
    w[(2, 3)] = -0.5;
    w[(3, 2)] = -0.5;
    w * 0.01
}

#[test]
fn below_the_level_the_joint_sticks_exactly() {
    let w = coupled_w();
    let v_free = Vector6::new(0.01, -0.005, 0.0, 0.002, 0.0, 0.0);
    let bound = Vector6::repeat(5.0);
    let mut lambda = Vector6::zeros();
    let v = solve_friction(&w, &v_free, &bound, &mut lambda);
    assert_eq!(v, Vector6::zeros());
    assert!(lambda.iter().zip(bound.iter()).all(|(l, b)| l.abs() <= *b));
}

#[test]
fn above_the_level_the_joint_slides_against_full_friction() {
    let w = coupled_w();
    let v_free = Vector6::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let bound = Vector6::new(3.0, 100.0, 0.0, 0.0, 0.0, 0.0);
    let mut lambda = Vector6::zeros();
    let v = solve_friction(&w, &v_free, &bound, &mut lambda);
    assert_eq!(lambda[0], -3.0, "sliding joint gets the full Coulomb level");
    assert!(v[0] > 0.0, "still moving forward: {v}");
    assert_eq!(v[1], 0.0, "joint 2 holds (its level is high)");
    // Complementarity: the joint without friction moves freely.
    assert_eq!(lambda[2], 0.0);
}

#[test]
fn friction_never_reverses_the_motion() {
    let w = Matrix6::identity() * 0.001;
    let v_free = Vector6::new(0.001, -0.001, 0.0, 0.0, 0.0, 0.0);
    let bound = Vector6::repeat(10.0);
    let mut lambda = Vector6::zeros();
    let v = solve_friction(&w, &v_free, &bound, &mut lambda);
    assert_eq!(
        v,
        Vector6::zeros(),
        "friction stops the joint, does not push it back"
    );
}

/// Bad input from the solver's side (`w`, the bounds, the warm start); `v_free` is the
/// caller's physics, and a velocity that is not a number there stays one.
#[test]
fn bad_input_gives_finite_output() {
    struct Case {
        what: &'static str,
        w: Matrix6<f64>,
        bound: Vector6<f64>,
        start: f64,
        /// A `w` that allows no solve: no friction this step (λ = 0, v = v_free).
        no_friction: bool,
    }
    let mut one_nan = coupled_w();
    one_nan[(0, 1)] = f64::NAN;
    let v_free = Vector6::new(0.01, -2.0, 0.0, 0.5, 0.0, 0.0);
    let bounds = Vector6::new(5.0, f64::NAN, -1.0, f64::INFINITY, 0.0, 1.0);
    let cases = [
        Case {
            what: "w all NaN",
            w: Matrix6::from_element(f64::NAN),
            bound: Vector6::repeat(1.0),
            start: 0.0,
            no_friction: true,
        },
        Case {
            what: "w with one NaN",
            w: one_nan,
            bound: Vector6::repeat(1.0),
            start: 0.0,
            no_friction: true,
        },
        Case {
            what: "w infinite",
            w: Matrix6::identity() * f64::INFINITY,
            bound: Vector6::repeat(1.0),
            start: 0.0,
            no_friction: true,
        },
        Case {
            what: "NaN, negative, infinite bounds",
            w: coupled_w(),
            bound: bounds,
            start: 0.0,
            no_friction: false,
        },
        Case {
            what: "NaN warm start",
            w: coupled_w(),
            bound: Vector6::repeat(1.0),
            start: f64::NAN,
            no_friction: false,
        },
        Case {
            what: "infinite warm start",
            w: coupled_w(),
            bound: Vector6::repeat(1.0),
            start: f64::INFINITY,
            no_friction: false,
        },
    ];
    for c in cases {
        let what = c.what;
        let mut lambda = Vector6::repeat(c.start);
        let v = solve_friction(&c.w, &v_free, &c.bound, &mut lambda);
        assert!(lambda.iter().all(|l| l.is_finite()), "{what}: λ = {lambda}");
        assert!(v.iter().all(|x| x.is_finite()), "{what}: v = {v}");
        if c.no_friction {
            assert_eq!(
                (v, lambda),
                (v_free, Vector6::zeros()),
                "{what}: no friction"
            );
        }
    }
}

/// The solution of the box-constrained problem is unique for a positive definite `w`: the
/// previous step's split (kept when it satisfies the conditions) and the Gauss-Seidel sweeps
/// (when it does not) must reach it from any warm start. Checked against the conditions
/// themselves and between a warm start from the solution, from zero and from the far bounds.
mod any_warm_start {
    use super::*;
    use proptest::prelude::*;

    fn spd(entries: &[f64], diag: &[f64]) -> Matrix6<f64> {
        let l = Matrix6::from_iterator(entries.iter().copied());
        let d = Matrix6::from_diagonal(&Vector6::from_iterator(diag.iter().copied()));
        (l * l.transpose() + d) * 0.01
    }

    proptest! {
        #[test]
        fn reaches_the_one_solution(
            entries in prop::collection::vec(-1.0f64..1.0, 36),
            diag in prop::collection::vec(0.05f64..2.0, 6),
            v_free in prop::collection::vec(-0.2f64..0.2, 6),
            bound in prop::collection::vec(0.0f64..8.0, 6),
            start in prop::collection::vec(-10.0f64..10.0, 6),
        ) {
            let w = spd(&entries, &diag);
            let v_free = Vector6::from_iterator(v_free);
            let bound = Vector6::from_iterator(bound);
            let mut warm = Vector6::from_iterator(start);
            let v = solve_friction(&w, &v_free, &bound, &mut warm);
            for i in 0..6 {
                let (l, b) = (warm[i], bound[i]);
                prop_assert!(l.abs() <= b, "λ{i} = {l} beyond its bound {b}");
                if b > 0.0 && l == b {
                    prop_assert!(v[i] <= 1e-12, "λ{i} = +F but v{i} = {}", v[i]);
                } else if b > 0.0 && l == -b {
                    prop_assert!(v[i] >= -1e-12, "λ{i} = -F but v{i} = {}", v[i]);
                } else if b > 0.0 {
                    prop_assert!(v[i].abs() <= 1e-12, "λ{i} inside but v{i} = {}", v[i]);
                }
            }
            for other in [Vector6::zeros(), bound, -bound, warm] {
                let mut lambda = other;
                let v2 = solve_friction(&w, &v_free, &bound, &mut lambda);
                prop_assert!((v2 - v).amax() <= 1e-9, "from {other}: v {v2} against {v}");
            }
        }
    }
}
