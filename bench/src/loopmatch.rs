//! Telling, from the published state alone, in which cycle an answer of the torque loop was
//! applied (pure, no I/O).
//!
//! In TORQUE_CONTROL the published `current` of an axis is the *commanded* current: the torque
//! the controller asked for in that cycle (gravity and friction compensation plus the last
//! accepted `set_torques`) divided by the axis's torque per ampere (`fill_view` in
//! rt-core/src/controller/mod.rs). The loop answers every state with a `set_torques` whose
//! axis-6 torque steps through [`LEVELS_NM`] by a counter; the axis-6 current of the state of the next cycle, times
//! the torque per ampere, less the compensation measured with zero torques (`baseline`), names
//! the level that was in force in that cycle. The levels stay below axis 6's Coulomb friction
//! (0.5 Nm), so the arm does not move and the compensation stays where it was measured. With
//! four levels an answer applied one, two or three cycles late shows another level, so a late
//! answer is never counted as on time.

/// Axis-6 torques the loop steps through [Nm].
pub const LEVELS_NM: [f64; 4] = [0.2, -0.2, 0.4, -0.4];
/// Largest distance from a level at which an observation still counts as that level [Nm].
pub const TOLERANCE_NM: f64 = 0.08;
/// Cycles after the next one in which a late answer is still looked for.
const LATE_LOOKAHEAD: u64 = 2;

/// The level the `k`-th answer sends.
pub fn level_of(k: u64) -> usize {
    (k % LEVELS_NM.len() as u64) as usize
}

/// The level an observed axis-6 torque [Nm] (baseline removed) shows, if any.
pub fn classify(torque_nm: f64) -> Option<usize> {
    LEVELS_NM
        .iter()
        .position(|l| (torque_nm - l).abs() <= TOLERANCE_NM)
}

/// The state of one cycle, as the loop saw it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observation {
    pub cycle: u64,
    /// The level in force in this cycle (`None`: none of the levels).
    pub level: Option<usize>,
}

/// One answer: sent on seeing the state of `cycle`, carrying `level`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Answer {
    pub cycle: u64,
    pub level: usize,
}

/// Where the answers were applied.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Tally {
    pub answers: u64,
    /// Applied in the very next cycle.
    pub next_cycle: u64,
    /// Seen one or two cycles later than that.
    pub late: u64,
    /// The next cycle's state was seen, and the answer was not in force in it nor soon after.
    pub never: u64,
    /// No state of the next cycle was seen (it cannot be told; counted as not on time).
    pub unobserved: u64,
}

impl Tally {
    /// Share of the answers applied in the very next cycle (0 with no answers).
    pub fn on_time_share(&self) -> f64 {
        if self.answers == 0 {
            0.0
        } else {
            self.next_cycle as f64 / self.answers as f64
        }
    }
}

/// Match each answer against the observations (sorted by cycle or not).
pub fn tally(observations: &[Observation], answers: &[Answer]) -> Tally {
    let mut by_cycle = std::collections::HashMap::with_capacity(observations.len());
    for o in observations {
        by_cycle.insert(o.cycle, o.level);
    }
    let mut t = Tally::default();
    for a in answers {
        t.answers += 1;
        match by_cycle.get(&(a.cycle + 1)) {
            None => t.unobserved += 1,
            Some(Some(l)) if *l == a.level => t.next_cycle += 1,
            Some(_) => {
                let later = (a.cycle + 2..=a.cycle + 1 + LATE_LOOKAHEAD)
                    .any(|c| by_cycle.get(&c) == Some(&Some(a.level)));
                if later {
                    t.late += 1;
                } else {
                    t.never += 1;
                }
            }
        }
    }
    t
}

/// Cycle numbers of states known only by their time stamps (status results over TCP): the
/// first is 0, each next one adds the number of whole periods since the previous one
/// (rounded), so a restarted deadline grid after an overrun does not shift the count.
/// Times must be strictly increasing.
pub fn cycle_numbers(times_s: &[f64], period_s: f64) -> Vec<u64> {
    let mut out = Vec::with_capacity(times_s.len());
    let mut n = 0u64;
    for (i, t) in times_s.iter().enumerate() {
        if i > 0 {
            let steps = ((t - times_s[i - 1]) / period_s).round().max(1.0);
            n += steps as u64;
        }
        out.push(n);
    }
    out
}

#[cfg(test)]
mod tests;
