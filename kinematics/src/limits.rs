//! Where each axis may be: its reachable range, a joint angle moved into it by whole turns,
//! and the distance that orders the solutions.

use mcm_shared::NUM_AXES;
use std::f64::consts::TAU;

/// How far outside its range a solution's axis may come out of the arithmetic and still count
/// as inside (it is then set onto the bound) [rad]: a seed on a limit comes back as itself.
pub const LIMIT_TOLERANCE_RAD: f64 = 1e-9;

/// An axis's reachable range [rad]: the software limits less the safety margin
/// (`mcm_shared::ranges::reachable_deg`), where a target may lie.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisRange {
    pub min: f64,
    pub max: f64,
}

/// How far a joint angle lies outside its range, when every whole-turn shift does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Miss {
    /// 0-based axis.
    pub axis: usize,
    /// The angle, shifted by whole turns to the side of the range nearest it [rad].
    pub value: f64,
    /// Distance from the range [rad].
    pub by: f64,
}

impl AxisRange {
    /// `angle` plus the whole number of turns that puts it within the range nearest `seed`; or
    /// how far it misses (the shift nearest the range).
    ///
    /// An axis whose range spans more than a turn has several such angles: the one nearest the
    /// seed is the one taken, so each branch of the solution gives one candidate.
    pub(crate) fn fit(&self, axis: usize, angle: f64, seed: f64) -> Result<f64, Miss> {
        // A seed beyond the range is as near to the range's values as its nearer bound is.
        let seed = seed.clamp(self.min, self.max);
        let mut v = angle + TAU * ((seed - angle) / TAU).round();
        if v > self.max + LIMIT_TOLERANCE_RAD {
            v -= TAU * ((v - self.max - LIMIT_TOLERANCE_RAD) / TAU).ceil();
        } else if v < self.min - LIMIT_TOLERANCE_RAD {
            v += TAU * ((self.min - LIMIT_TOLERANCE_RAD - v) / TAU).ceil();
        }
        if v < self.min - LIMIT_TOLERANCE_RAD || v > self.max + LIMIT_TOLERANCE_RAD {
            // The range lies between two whole-turn shifts: report the nearer one.
            let below = if v < self.min { v } else { v - TAU };
            let above = below + TAU;
            let (value, by) = if self.min - below <= above - self.max {
                (below, self.min - below)
            } else {
                (above, above - self.max)
            };
            return Err(Miss { axis, value, by });
        }
        Ok(v.clamp(self.min, self.max))
    }
}

/// The distance from `from` to `to` that orders the solutions: the time the slowest axis needs
/// at its maximum velocity, max over axes of |Δq| / v_max [s] (`speed` in rad/s). The sum of
/// the squared times breaks ties (it is the second element).
pub fn travel_time(
    from: &[f64; NUM_AXES],
    to: &[f64; NUM_AXES],
    speed: &[f64; NUM_AXES],
) -> (f64, f64) {
    let mut max: f64 = 0.0;
    let mut sum = 0.0;
    for ((a, b), v) in from.iter().zip(to).zip(speed) {
        let t = (b - a).abs() / v;
        max = max.max(t);
        sum += t * t;
    }
    (max, sum)
}

#[cfg(test)]
mod tests;
