use super::*;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
}

#[test]
fn the_cubic_meets_both_knots() {
    let k0 = Knot {
        p: 0.3,
        v: -0.2,
        a: None,
    };
    let k1 = Knot {
        p: 1.1,
        v: 0.7,
        a: Some(5.0),
    };
    let poly = Polynomial::hermite(k0, k1, 0.8);
    let (p, v, _) = poly.eval(0.0);
    assert_eq!((p, v), (0.3, -0.2));
    let (p, v, _) = poly.eval(0.8);
    assert!(close(p, 1.1) && close(v, 0.7), "{p} {v}");
}

#[test]
fn the_quintic_meets_both_knots_with_their_accelerations() {
    let k0 = Knot {
        p: -0.4,
        v: 0.5,
        a: Some(-1.5),
    };
    let k1 = Knot {
        p: 0.9,
        v: -0.3,
        a: Some(2.5),
    };
    let poly = Polynomial::hermite(k0, k1, 1.3);
    assert_eq!(poly.eval(0.0), (-0.4, 0.5, -1.5));
    let (p, v, a) = poly.eval(1.3);
    assert!(
        close(p, 0.9) && close(v, -0.3) && close(a, 2.5),
        "{p} {v} {a}"
    );
}

#[test]
fn derivatives_match_finite_differences() {
    let k0 = Knot {
        p: 0.1,
        v: 0.2,
        a: Some(0.3),
    };
    let k1 = Knot {
        p: 1.0,
        v: -0.4,
        a: Some(-2.0),
    };
    let poly = Polynomial::hermite(k0, k1, 0.7);
    let h = 1e-6;
    for tau in [0.1, 0.35, 0.6] {
        let (p0, v0, _) = poly.eval(tau - h);
        let (p1, v1, _) = poly.eval(tau + h);
        let (_, v, a) = poly.eval(tau);
        assert!(
            (v - (p1 - p0) / (2.0 * h)).abs() < 1e-6,
            "velocity at {tau}"
        );
        assert!(
            (a - (v1 - v0) / (2.0 * h)).abs() < 1e-5,
            "acceleration at {tau}"
        );
    }
}
