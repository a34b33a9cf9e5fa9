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
//! satisfies all three for long enough. The baseline learns only while the axis follows its
//! target, never while a run is under way (and, in the slow approach, not once it settled), so
//! a slow rise against a soft stop does not hide in it, and an axis that starts against its
//! stop or an obstacle still sees its contact.

/// Time the baseline must have been tracked before a contact is trusted [s].
pub const SETTLE: f64 = 0.25;
/// Smoothing factor of the current baseline per cycle.
const BASELINE_ALPHA: f64 = 0.05;
/// A run survives this many cycles in a row without the current beyond the threshold (one
/// bad sample, a spike against the push, does not end a real contact; it does not count).
const MISSES_ALLOWED: u32 = 1;

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
    /// The baseline follows the current while armed (a long fast search through changing
    /// gravity); else it is frozen once settled (a short slow approach, so that the slow rise
    /// against a soft stop cannot hide in it).
    pub track_armed: bool,
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
        let push = direction * (current - self.baseline) > p.threshold;
        let watching = armed && self.settled();
        if watching && !push && self.run > 0 && self.misses < MISSES_ALLOWED {
            self.misses += 1;
            return None;
        }
        self.misses = 0;
        if !(watching && push) {
            // The baseline is the current of free motion: it learns only while the axis
            // follows its target (an axis that starts against its stop or an obstacle must not
            // teach it the pushing current).
            let following = direction * (target - position) < p.min_lag;
            if (watching && !p.track_armed) || !following {
                self.run = 0;
                self.age += dt;
            } else {
                self.track(current, dt);
            }
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
        let lag = direction * (target - position);
        let commanded = direction * (target - self.mid_target);
        let advanced = direction * (position - self.mid_position);
        if lag >= p.min_lag && commanded > 0.0 && advanced <= p.stall_fraction * commanded {
            return Some(self.onset_position);
        }
        // Still pushing but still moving: judge the stall again over the next half run.
        self.run = half;
        self.mid_position = position;
        self.mid_target = target;
        None
    }
}

#[cfg(test)]
mod tests;
