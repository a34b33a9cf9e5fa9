//! Contact with a mechanical stop, decided from positions and currents over time, never from
//! one sample.
//!
//! Runs inside the cycle: plain `Copy` data and arithmetic, no allocation.
//!
//! Contact is declared only when, for [`ContactParams::confirm_cycles`] cycles in a row (a
//! single sample that misses does not end the run, nor count):
//! - the motor current departs from its free-motion baseline by more than
//!   [`ContactParams::threshold`] *in the search direction* (a stop is pushed against; a jolt
//!   from another axis swings both ways),
//! - and at the end the following error (the target the measured position answers, two cycles
//!   old, minus the measured position, in the search direction) is at least
//!   [`ContactParams::min_lag`],
//! - and the axis no longer advances: over the last half of the run it moved less than
//!   [`ContactParams::stall_fraction`] of what its target moved.
//!
//! The contact position is where the run began (the first cycle of the current's departure):
//! the least compressed stop. A late cycle, a current spike or another axis's impact makes the
//! current depart for a cycle or two while the axis keeps following its target; it never
//! satisfies all three for long enough.
//!
//! **Quiet time.** The arm couples its axes: another axis hitting its stop at search speed
//! throws this one about (ahead of its target, then back), and its current swings against the
//! search direction and then with it. The half of the swing with the search direction, with
//! the axis held back, looks like a contact. So a run is dropped, and none starts for
//! [`QUIET`], when
//! - the current departs *against* the search direction by more than the threshold for
//!   [`SWING_CYCLES`] cycles in a row (a stop never pulls the axis on; a spike lasts one
//!   cycle), or
//! - a run is judged while the axis still follows its target (within
//!   [`ContactParams::min_lag`]): its free-motion current changed (the gravity load moves with
//!   the other axes), no stop was touched, and a run kept going would keep its onset, far
//!   back, for whatever holds the axis later.
//!
//! **Baseline.** The baseline learns only while the axis follows its target within
//! [`ContactParams::min_lag`] either way (an axis that lags presses on something; one that runs
//! ahead is moved by something else) and no run is under way, in the quiet time too (it learns
//! the load as it is after a swing or a change). It is not frozen in the slow approach: the
//! other axes' searches change this axis's gravity load by amperes within one approach. A slow
//! rise against a stop does not hide in it, because an axis held by a stop falls behind its
//! target by [`ContactParams::min_lag`] within a few cycles and the baseline stops learning.
//! An axis that starts against its stop or an obstacle lags from the start and still sees its
//! contact.

/// Time the baseline must have been tracked before a contact is trusted [s].
pub const SETTLE: f64 = 0.25;
/// Smoothing factor of the current baseline per cycle.
const BASELINE_ALPHA: f64 = 0.05;
/// A run survives this many cycles in a row without the current beyond the threshold (one
/// bad sample, a spike against the push, does not end a real contact; it does not count).
const MISSES_ALLOWED: u32 = 1;
/// Cycles in a row the current must depart against the search direction to be a swing (the
/// axis moved by something else), not a spike.
pub const SWING_CYCLES: u32 = 2;
/// After a swing, or a run judged while the axis followed its target, no run starts for this
/// long [s]: a jolt from another axis's impact rings for about a tenth of a second.
pub const QUIET: f64 = 0.25;

/// How strict the detection is in one phase of the search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactParams {
    /// Current beyond the baseline in the search direction [A].
    pub threshold: f64,
    /// Cycles in a row the current must stay beyond the threshold.
    pub confirm_cycles: u32,
    /// Least following error in the search direction at the confirmation [rad].
    pub min_lag: f64,
    /// Largest share of its target's advance the axis may still make over the last half of
    /// the run (a stop holds the axis; free motion follows the target).
    pub stall_fraction: f64,
}

/// One cycle's measurement: the measured raw `position` [rad] and motor `current` [A], and
/// `target`, the position target the measurement answers (sent two cycles ago) [rad].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub position: f64,
    pub current: f64,
    pub target: f64,
}

/// The detector of one search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactDetector {
    baseline: f64,
    /// Time the baseline has been tracked since the last restart [s].
    age: f64,
    /// Cycles with the current beyond the threshold in the current run.
    run: u32,
    /// Cycles in a row the current was not beyond the threshold during the run.
    misses: u32,
    onset_position: f64,
    /// Position and target at the middle of the run (the stall is judged since then).
    mid_position: f64,
    mid_target: f64,
    /// Cycles in a row the current departed against the search direction.
    against: u32,
    /// Time left before a run may start [s] (see the module's "Quiet time").
    quiet: f64,
}

impl ContactDetector {
    /// A detector whose baseline starts at `current` (not yet settled).
    pub fn new(current: f64) -> ContactDetector {
        ContactDetector {
            baseline: current,
            age: 0.0,
            run: 0,
            misses: 0,
            onset_position: 0.0,
            mid_position: 0.0,
            mid_target: 0.0,
            against: 0,
            quiet: 0.0,
        }
    }

    /// The free-motion current baseline [A].
    pub fn baseline(&self) -> f64 {
        self.baseline
    }

    /// The baseline has been tracked long enough to be trusted.
    pub fn settled(&self) -> bool {
        self.age >= SETTLE
    }

    /// Start settling again (the motion changed: a new phase), keeping the baseline's value.
    pub fn restart(&mut self) {
        self.age = 0.0;
        self.run = 0;
        self.against = 0;
        self.quiet = 0.0;
    }

    /// Start settling again from `current` (after a back-off: the old baseline belongs to
    /// another motion).
    pub fn rebase(&mut self, current: f64) {
        self.baseline = current;
        self.restart();
    }

    /// Track the baseline only (the axis holds or ramps; no contact is looked for).
    pub fn track(&mut self, current: f64, dt: f64) {
        self.run = 0;
        self.baseline += BASELINE_ALPHA * (current - self.baseline);
        self.age += dt;
    }

    /// One cycle of a search in `direction` (+1/-1) with this cycle's [`Sample`]. `armed`:
    /// the search runs at its speed (contact is looked for only then, and only once the
    /// baseline settled). The contact position once confirmed.
    pub fn step(
        &mut self,
        p: &ContactParams,
        direction: f64,
        sample: Sample,
        armed: bool,
        dt: f64,
    ) -> Option<f64> {
        let Sample {
            position,
            current,
            target,
        } = sample;
        let departure = direction * (current - self.baseline);
        let push = departure > p.threshold;
        let lag = direction * (target - position);
        let following = lag.abs() < p.min_lag;
        let watching = armed && self.settled();
        self.against = if departure < -p.threshold {
            self.against + 1
        } else {
            0
        };
        if watching && self.against >= SWING_CYCLES {
            // A swing: something else moves the axis; what follows is no contact.
            self.quiet = QUIET;
        }
        if self.quiet > 0.0 {
            self.quiet -= dt;
            self.run = 0;
            self.misses = 0;
            self.learn(following, current, dt);
            return None;
        }
        if watching && !push && self.run > 0 && self.misses < MISSES_ALLOWED {
            self.misses += 1;
            return None;
        }
        self.misses = 0;
        if !(watching && push) {
            self.run = 0;
            self.learn(following, current, dt);
            return None;
        }
        self.run += 1;
        if self.run == 1 {
            self.onset_position = position;
        }
        let half = (p.confirm_cycles / 2).max(1);
        if self.run == half {
            self.mid_position = position;
            self.mid_target = target;
        }
        if self.run < p.confirm_cycles {
            return None;
        }
        let commanded = direction * (target - self.mid_target);
        let advanced = direction * (position - self.mid_position);
        if lag >= p.min_lag && commanded > 0.0 && advanced <= p.stall_fraction * commanded {
            return Some(self.onset_position);
        }
        if following {
            // The current is up but the axis follows: its load changed, no stop was touched.
            self.run = 0;
            self.quiet = QUIET;
            return None;
        }
        // Still pushing but still moving: judge the stall again over the next half run.
        self.run = half;
        self.mid_position = position;
        self.mid_target = target;
        None
    }

    /// No run this cycle: the baseline learns the current if the axis follows its target (an
    /// axis that lags presses on something, one that runs ahead is moved by something else).
    fn learn(&mut self, following: bool, current: f64, dt: f64) {
        if following {
            self.track(current, dt);
        } else {
            self.age += dt;
        }
    }
}

#[cfg(test)]
mod tests;
