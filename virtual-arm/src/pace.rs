//! When a period passes for the virtual arm: with each SYNC the master sends, as on the
//! in-process simulated bus, or, when none comes, on the wall clock.
//!
//! A real arm's physics never waits for the master. So that a stalled or stopped master does
//! not freeze the virtual arm's time, [`Pace`] keeps the periods passed within `grace` periods
//! of the wall clock: when the periods due by the clock run more than `grace` ahead of the
//! periods passed, the arm runs periods without SYNC (the drives hold their last setpoint,
//! send no PDO, keep their heartbeats; `SimBus::period_without_sync`). When SYNCs come faster
//! than the clock (after a stall, a burst), the clock is re-anchored instead, so that the arm's
//! time never runs ahead of the master's by more than it did.
//!
//! ```
//! use mcm_virtual_arm::pace::Pace;
//! let mut pace = Pace::new(5_000_000, 2, 0);
//! pace.on_sync(5_000_000);
//! assert_eq!(pace.overdue(14_000_000), 0); // 2 due, 1 passed: within the grace
//! assert_eq!(pace.overdue(20_000_000), 1); // 4 due, 1 passed: one period without SYNC
//! ```

/// Periods of the arm against the wall clock (`CLOCK_MONOTONIC` nanoseconds).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pace {
    period_ns: u64,
    grace: u64,
    /// Wall time at which zero periods were due.
    anchor_ns: u64,
    /// Periods passed (with or without SYNC) since the anchor.
    passed: u64,
}

impl Pace {
    /// Start at `now_ns` with periods of `period_ns` (at least 1) and a grace of `grace`
    /// periods.
    pub fn new(period_ns: u64, grace: u64, now_ns: u64) -> Pace {
        Pace {
            period_ns: period_ns.max(1),
            grace,
            anchor_ns: now_ns,
            passed: 0,
        }
    }

    fn due(&self, now_ns: u64) -> u64 {
        now_ns.saturating_sub(self.anchor_ns) / self.period_ns
    }

    /// A SYNC arrived at `now_ns`: a period passes with it.
    pub fn on_sync(&mut self, now_ns: u64) {
        self.passed += 1;
        let due = self.due(now_ns);
        if self.passed > due + self.grace {
            self.passed = 0;
            self.anchor_ns = now_ns;
        }
    }

    /// How many periods without SYNC to run at `now_ns` (they count as passed).
    pub fn overdue(&mut self, now_ns: u64) -> u64 {
        let due = self.due(now_ns);
        let late = due.saturating_sub(self.passed + self.grace);
        self.passed += late;
        late
    }

    /// The wall time by which, without a SYNC, the next period without one is due.
    pub fn deadline_ns(&self) -> u64 {
        self.anchor_ns
            .saturating_add((self.passed + self.grace + 1).saturating_mul(self.period_ns))
    }
}

#[cfg(test)]
mod tests;
