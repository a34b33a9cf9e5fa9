//! Velocities for knots that the goal gives none for, so that the path has no velocity step.
//!
//! The rule (per axis, as in a monotone piecewise cubic "PCHIP", Fritsch and Butland):
//! at an interior knot with the slopes s0 (from the previous knot) and s1 (to the next), over
//! the spans h0 and h1, the velocity is 0 where the slope changes sign or either is 0 (the knot
//! is a turning point: the path stops there instead of overshooting), and otherwise the
//! weighted harmonic mean (w1 + w2) / (w1/s0 + w2/s1) with w1 = 2·h1 + h0, w2 = h1 + 2·h0. It
//! lies between the two slopes and never exceeds three times the smaller, so between knots
//! without given velocities the path never leaves the range of its two knots. The last knot's
//! velocity is 0 when not given. A given velocity is kept.

use mcm_shared::NUM_AXES;

/// The velocity of every knot: `given[k]` where it is `Some`, else estimated as the module
/// says. The three slices have the same length, `times` strictly increasing.
pub fn fill(
    times: &[f64],
    positions: &[[f64; NUM_AXES]],
    given: &[Option<[f64; NUM_AXES]>],
) -> Vec<[f64; NUM_AXES]> {
    let n = times.len();
    (0..n)
        .map(|k| {
            if let Some(v) = given[k] {
                return v;
            }
            if k == 0 || k + 1 == n {
                return [0.0; NUM_AXES];
            }
            let (h0, h1) = (times[k] - times[k - 1], times[k + 1] - times[k]);
            std::array::from_fn(|axis| {
                let s0 = (positions[k][axis] - positions[k - 1][axis]) / h0;
                let s1 = (positions[k + 1][axis] - positions[k][axis]) / h1;
                interior(s0, s1, h0, h1)
            })
        })
        .collect()
}

/// The estimate at an interior knot (see the module doc).
fn interior(s0: f64, s1: f64, h0: f64, h1: f64) -> f64 {
    if s0 * s1 <= 0.0 {
        return 0.0;
    }
    let (w1, w2) = (2.0 * h1 + h0, h1 + 2.0 * h0);
    (w1 + w2) / (w1 / s0 + w2 / s1)
}

#[cfg(test)]
mod tests;
