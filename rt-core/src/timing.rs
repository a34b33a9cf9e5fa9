//! The loop's timing figures: wake-up latency since start and over a recent window, and the
//! cycle's work time against its budget ([`CycleTiming`] of the state sample).
//!
//! Runs inside the cycle. Everything is allocated by [`Timing::new`]. Recording is a few
//! integer operations; the percentiles are computed every `refresh_cycles` cycles only (one
//! pass over the since-start histogram, and a merge of the window's sub-histograms plus one
//! pass over the result), so the per-cycle cost stays small and bounded; between two
//! refreshes the published percentiles are those of the last refresh.
//!
//! The recent window is a ring of [`WINDOW_SLOTS`] sub-histograms of one slot each (e.g. 1 s
//! of cycles): the figures cover the full slots before the current one plus the current one,
//! i.e. between `WINDOW_SLOTS - 1` and `WINDOW_SLOTS` slots. Time is counted in cycles (the
//! robot's own clock), so the window's span is `cycles x period`.

use crate::histogram::Histogram;
use mcm_shared::sample::{CycleTiming, LatencyFigures};

/// Sub-histograms of the recent window.
pub const WINDOW_SLOTS: usize = 10;

/// Timing figures of the running loop.
pub struct Timing {
    period_ns: u64,
    work_budget_ns: u64,
    since_start: Box<Histogram>,
    slots: Box<[Histogram]>,
    slot: usize,
    slot_cycles: u64,
    in_slot: u64,
    merged: Box<Histogram>,
    refresh_cycles: u64,
    since_refresh: u64,
    since_start_figures: LatencyFigures,
    recent_figures: LatencyFigures,
    work_max_ns: u64,
    over_budget: u64,
}

impl Timing {
    /// Figures of a loop at `period_ns` whose work should take at most `work_budget_ns`; the
    /// window's slots span `slot_ns` each (at least one cycle), the percentiles are computed
    /// every `refresh_cycles` cycles (at least 1).
    pub fn new(period_ns: u64, work_budget_ns: u64, slot_ns: u64, refresh_cycles: u64) -> Self {
        let refresh_cycles = refresh_cycles.max(1);
        Self {
            period_ns,
            work_budget_ns,
            since_start: Box::new(Histogram::new()),
            slots: vec![Histogram::new(); WINDOW_SLOTS].into_boxed_slice(),
            slot: 0,
            slot_cycles: (slot_ns / period_ns.max(1)).max(1),
            in_slot: 0,
            merged: Box::new(Histogram::new()),
            refresh_cycles,
            since_refresh: refresh_cycles,
            since_start_figures: LatencyFigures::default(),
            recent_figures: LatencyFigures::default(),
            work_max_ns: 0,
            over_budget: 0,
        }
    }

    /// A cycle woke `latency_ns` after its deadline.
    pub fn wake(&mut self, latency_ns: u64) {
        self.since_start.record(latency_ns);
        if self.in_slot == self.slot_cycles {
            self.slot = (self.slot + 1) % WINDOW_SLOTS;
            self.slots[self.slot].clear();
            self.in_slot = 0;
        }
        self.slots[self.slot].record(latency_ns);
        self.in_slot += 1;
        self.since_refresh += 1;
        if self.since_refresh >= self.refresh_cycles {
            self.since_refresh = 0;
            self.since_start_figures = self.since_start.figures();
            self.merged.clear();
            for h in self.slots.iter() {
                self.merged.merge(h);
            }
            self.recent_figures = self.merged.figures();
        }
    }

    /// A cycle's work took `work_ns`.
    pub fn work(&mut self, work_ns: u64) {
        self.work_max_ns = self.work_max_ns.max(work_ns);
        if work_ns > self.work_budget_ns {
            self.over_budget += 1;
        }
    }

    /// The figures as of the last refresh (percentiles) and now (counts), with `overruns`.
    pub fn figures(&self, overruns: u64) -> CycleTiming {
        CycleTiming {
            period_ns: self.period_ns,
            overruns,
            since_start: self.since_start_figures,
            recent: self.recent_figures,
            recent_window_ns: self.recent_figures.cycles * self.period_ns,
            work_max_ns: self.work_max_ns,
            work_budget_ns: self.work_budget_ns,
            over_budget: self.over_budget,
        }
    }

    /// Wake-up latency since start, exact as of now (not only at the last refresh).
    pub fn since_start(&self) -> &Histogram {
        &self.since_start
    }
}

#[cfg(test)]
mod tests;
