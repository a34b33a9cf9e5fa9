//! How the real-time loop ends: the first SIGINT/SIGTERM starts the controller's shutdown
//! (controlled stop, hold, disable the drives: `controller/shutdown_sequence.rs`), the loop runs on
//! until the controller says it finished, and a second signal ends it at once.
//!
//! [`StopSequence::poll`] runs in the real-time loop, between cycles: no allocation, no lock,
//! no logging (the outcome is logged by the runner after the loop, [`StopOutcome`]'s
//! `Display`).

use crate::controller::{Controller, ShutdownPhase, ShutdownResult};

/// A further signal within this time of the first counts as the same request (a process
/// group and its supervisor often signal together).
pub const SECOND_SIGNAL_DEBOUNCE_NS: u64 = 250_000_000;
/// After the shutdown finished, the loop goes on publishing this long (the drives disabled,
/// mode OFF, `STATE_SHUTTING_DOWN`), so that readers see the final state before it stops.
pub const FINAL_STATE_NS: u64 = 100_000_000;
/// Wall-clock allowance over the controller's bound (the controller's time runs behind the
/// wall clock when cycles overrun) before the drives are disabled regardless.
const WALL_ALLOWANCE_NS: u64 = 1_000_000_000;

/// How the loop ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopOutcome {
    /// The shutdown finished; `took_ns` of wall-clock time since the first signal.
    Finished {
        result: ShutdownResult,
        took_ns: u64,
        bound_ns: u64,
    },
    /// A second signal ended the shutdown at once, in `phase`.
    Interrupted { phase: ShutdownPhase, after_ns: u64 },
}

impl std::fmt::Display for StopOutcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = |ns: u64| ns as f64 / 1e9;
        match *self {
            StopOutcome::Finished {
                result,
                took_ns,
                bound_ns,
            } => write!(
                f,
                "controlled stop took {:.3} s (bound {:.1} s): {result}",
                s(took_ns),
                s(bound_ns)
            ),
            StopOutcome::Interrupted { phase, after_ns } => {
                let what = match phase {
                    ShutdownPhase::Requested | ShutdownPhase::Stopping => {
                        "while the arm was stopping"
                    }
                    ShutdownPhase::Holding { .. } => "while holding at standstill",
                    ShutdownPhase::Disabling => "while the drives were disabling",
                    ShutdownPhase::Done(_) => "as it finished",
                };
                write!(
                    f,
                    "a second stop signal ended the controlled stop at once after {:.3} s, {what}; \
                     the drives were not disabled by mcm-rt (they stop on their heartbeat timeout)",
                    s(after_ns)
                )
            }
        }
    }
}

/// The stop signals seen by the loop.
#[derive(Debug, Clone, Copy, Default)]
pub struct StopSequence {
    /// Signals counted when the loop started.
    baseline: usize,
    /// Once a stop was asked for: the signal count absorbed and the wall time of the first.
    started: Option<(usize, u64)>,
    /// Once the shutdown finished: how, and the wall time it was seen.
    finished: Option<(StopOutcome, u64)>,
}

impl StopSequence {
    /// Start watching; `signals` is the current count ([`crate::signals::count`]).
    pub fn new(signals: usize) -> Self {
        Self {
            baseline: signals,
            started: None,
            finished: None,
        }
    }

    /// Whether a stop was asked for.
    pub fn stopping(&self) -> bool {
        self.started.is_some()
    }

    /// After each cycle, with the signal count and the wall clock: `Some` when the loop ends.
    pub fn poll(
        &mut self,
        controller: &mut Controller,
        signals: usize,
        wall_ns: u64,
    ) -> Option<StopOutcome> {
        let Some((seen, since)) = self.started else {
            if signals > self.baseline {
                controller.begin_shutdown();
                self.started = Some((signals, wall_ns));
            }
            return None;
        };
        let after_ns = wall_ns.saturating_sub(since);
        if let Some((outcome, at)) = self.finished {
            // A further signal now only cuts the final publishing short.
            let done = signals > seen || wall_ns.saturating_sub(at) >= FINAL_STATE_NS;
            return done.then_some(outcome);
        }
        if signals > seen {
            if after_ns < SECOND_SIGNAL_DEBOUNCE_NS {
                self.started = Some((signals, since));
            } else {
                let phase = controller
                    .shutdown_status()
                    .map_or(ShutdownPhase::Requested, |s| s.phase);
                return Some(StopOutcome::Interrupted { phase, after_ns });
            }
        }
        let bound_ns = controller.shutdown_bound_ns();
        if let Some(result) = controller.shutdown_status().and_then(|s| s.result()) {
            let outcome = StopOutcome::Finished {
                result,
                took_ns: after_ns,
                bound_ns,
            };
            self.finished = Some((outcome, wall_ns));
            return None;
        }
        if after_ns > bound_ns + WALL_ALLOWANCE_NS {
            // The next cycle sends the disable; the one after reports it finished.
            controller.end_shutdown_now();
        }
        None
    }
}

// The tests run the whole simulated robot.
#[cfg(all(test, feature = "sim"))]
mod tests;
