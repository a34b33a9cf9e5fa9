//! One axis's path between two knots: the cubic Hermite polynomial through (position,
//! velocity) at both ends, or the quintic one through (position, velocity, acceleration).

/// A knot of one axis: position [rad], velocity [rad/s] and, for a quintic, acceleration
/// [rad/s²].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Knot {
    pub p: f64,
    pub v: f64,
    pub a: Option<f64>,
}

/// p(τ) = Σ c[i]·τ^i for τ in [0, T].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Polynomial {
    c: [f64; 6],
}

impl Polynomial {
    /// The polynomial from `k0` at τ = 0 to `k1` at τ = `span` (> 0): quintic when both knots
    /// have an acceleration, cubic otherwise.
    pub fn hermite(k0: Knot, k1: Knot, span: f64) -> Polynomial {
        let (t, d) = (span, k1.p - k0.p);
        let (v0, v1) = (k0.v, k1.v);
        let c = match (k0.a, k1.a) {
            (Some(a0), Some(a1)) => {
                let (t2, t3) = (t * t, t * t * t);
                [
                    k0.p,
                    v0,
                    a0 / 2.0,
                    (20.0 * d - (8.0 * v1 + 12.0 * v0) * t - (3.0 * a0 - a1) * t2) / (2.0 * t3),
                    (-30.0 * d + (14.0 * v1 + 16.0 * v0) * t + (3.0 * a0 - 2.0 * a1) * t2)
                        / (2.0 * t3 * t),
                    (12.0 * d - 6.0 * (v1 + v0) * t - (a0 - a1) * t2) / (2.0 * t3 * t2),
                ]
            }
            _ => [
                k0.p,
                v0,
                (3.0 * d / t - 2.0 * v0 - v1) / t,
                (-2.0 * d / t + v0 + v1) / (t * t),
                0.0,
                0.0,
            ],
        };
        Polynomial { c }
    }

    /// (position, velocity, acceleration) at τ.
    pub fn eval(&self, tau: f64) -> (f64, f64, f64) {
        let c = &self.c;
        let p = c[0] + tau * (c[1] + tau * (c[2] + tau * (c[3] + tau * (c[4] + tau * c[5]))));
        let v =
            c[1] + tau * (2.0 * c[2] + tau * (3.0 * c[3] + tau * (4.0 * c[4] + tau * 5.0 * c[5])));
        let a = 2.0 * c[2] + tau * (6.0 * c[3] + tau * (12.0 * c[4] + tau * 20.0 * c[5]));
        (p, v, a)
    }
}

#[cfg(test)]
mod tests;
