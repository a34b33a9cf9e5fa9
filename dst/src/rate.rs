//! Durations in cycles of the configured cycle rate: what the run's senders wait and how long
//! faults last are given in seconds, so that they mean the same at any `cycle.rate_hz`.

use mcm_shared::config::RobotConfig;

/// The cycle rate of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rate {
    hz: f64,
}

impl Rate {
    pub fn of(cfg: &RobotConfig) -> Rate {
        Rate {
            hz: f64::from(cfg.cycle.rate_hz),
        }
    }

    /// `seconds` in whole cycles (rounded; at least one).
    pub fn cycles(self, seconds: f64) -> u64 {
        ((seconds * self.hz).round() as u64).max(1)
    }
}
