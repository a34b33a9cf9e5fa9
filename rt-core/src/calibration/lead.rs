//! How far a search's target may run ahead of the measured position.
//!
//! Runs inside the cycle: plain `Copy` data and arithmetic, no allocation.
//!
//! The contact detector sees a stop from the current it takes to push against it. An axis held
//! by something whose current cannot show it (an obstacle while its current is derated by i2t:
//! the derated limit is the baseline the detector learned, so the current never departs) would
//! let the search's target run on for the whole search range while the axis stands still, and
//! no safety check watches the following error during a search: the drive's position loop then
//! throws the axis at the far target as soon as it is free.
//!
//! So the target may lead the position it is answered by (the target two cycles old) by at
//! most [`bound`]: the axis's following-error band (what any other mode tolerates before a
//! trip) plus the distance the target travels while the detector confirms a contact at the
//! search speed (its run of confirmation cycles, one cycle it may miss, and the two cycles of
//! feedback latency). Within that the detector decides; an axis that falls further behind:
//! - stops its target where it is (it advances no further),
//! - is in contact if, for the detector's confirmation cycles in a row, its current departs
//!   beyond the detector's threshold in the search direction while it stands still (it
//!   advances less than the detector's least lag): a stop the detector did not confirm in time
//!   (it was in its quiet time after another axis's impact, or the search was still ramping up
//!   when the axis started against its stop); the contact is where the axis stands;
//! - is waited for while it still advances: an axis that gains at least the detector's least
//!   lag in the search direction within the detector's confirmation and latency cycles lags
//!   (the other axes' searches load it), it is not held, and with its target standing it
//!   catches up;
//! - else it is blocked (it stood, or went back, for the confirmation and latency cycles
//!   without a push): the calibration fails, naming the lag and the bound.
//!
//! An axis that catches up within the bound again (whatever held it let go) searches on. The
//! target only ever advances while the axis is within the bound, so it never leads by more
//! than the bound and one cycle's step; while the target stands, an axis that advances
//! shrinks its lag, so the wait for it is bounded by the lag over the least lag.

use super::contact::ContactParams;

/// Cycles beyond the confirmation run the detector may take: one missed sample and the two
/// cycles the measured position lags its target.
const LATENCY_CYCLES: u32 = 3;

/// The largest lead of the target over the position it is answered by [rad]: the
/// following-error `band` [rad] plus what a search at `speed` [rad/s] travels in
/// `confirm_cycles` cycles of `dt` [s] and the detector's latency.
pub fn bound(band: f64, speed: f64, confirm_cycles: u32, dt: f64) -> f64 {
    band + speed.abs() * f64::from(confirm_cycles + LATENCY_CYCLES) * dt
}

/// What the search does this cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Verdict {
    /// The axis is within the bound: the target advances.
    Advance,
    /// The axis is beyond the bound: the target stays where it is while the current is judged.
    Stay,
    /// The axis pushes against something where it stands (raw position).
    Contact(f64),
    /// The axis stayed beyond the bound with no push: lag [rad].
    Blocked(f64),
}

/// The guard of one search.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LeadGuard {
    /// Cycles the axis has been beyond the bound (0: within).
    held: u32,
    /// Cycles in a row of those its current pushed in the search direction.
    pushes: u32,
    /// Where the axis stood when it went beyond the bound, or when it last advanced the
    /// detector's least lag since.
    from: f64,
}

impl LeadGuard {
    /// One cycle: `lag` = (target answered - position) in the search direction [rad],
    /// `position` the measured (raw) position [rad], `direction` the search's (+1/-1),
    /// `push` = the current departs beyond the detector's threshold in the search direction;
    /// the confirmation cycles and the least lag [rad] are the detector's (`params`).
    pub fn step(
        &mut self,
        lag: f64,
        bound: f64,
        position: f64,
        direction: f64,
        push: bool,
        params: &ContactParams,
    ) -> Verdict {
        let (confirm_cycles, min_lag) = (params.confirm_cycles, params.min_lag);
        if lag <= bound {
            // Within the bound (again: whatever held the axis let it go and it caught up).
            *self = LeadGuard::default();
            return Verdict::Advance;
        }
        if self.held == 0 {
            self.from = position;
        }
        self.held += 1;
        let advanced = direction * (position - self.from);
        if advanced >= min_lag {
            // Still advancing: a lagging axis, not a held one; its target waits for it.
            *self = LeadGuard {
                held: 1,
                pushes: 0,
                from: position,
            };
            return Verdict::Stay;
        }
        let still = advanced.abs() < min_lag;
        self.pushes = if push && still { self.pushes + 1 } else { 0 };
        if self.pushes >= confirm_cycles {
            return Verdict::Contact(position);
        }
        if self.held >= confirm_cycles + LATENCY_CYCLES {
            return Verdict::Blocked(lag);
        }
        Verdict::Stay
    }
}

#[cfg(test)]
mod tests;
