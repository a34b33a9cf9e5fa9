//! How a gateway that dies is restarted, defined once for both supervisors: the `mcm`
//! launcher computes its waits with [`RestartPolicy::delay`], and the systemd unit
//! `deploy/systemd/mcm-gateway.service` carries the same numbers as `RestartSec=`,
//! `RestartSteps=` and `RestartMaxDelaySec=` ([`RestartPolicy::systemd_lines`]; systemd 254 or
//! later, which computes the same waits; a test checks the unit file).
//!
//! The ROS 2 node (`mcm-ros2`) is restarted after a fixed wait, [`ROS2_RESTART`], by the
//! launcher and by `deploy/systemd/mcm-ros2.service` alike (the same test checks that unit).
//!
//! The real-time core is never restarted by either: a dead `mcm-rt` on a robot is not
//! something to paper over (the launcher stops everything, its unit says `Restart=no`).
//!
//! One difference remains: the launcher starts again from the first wait after the gateway ran
//! for [`RestartPolicy::healthy_run`]; systemd keeps counting restarts until the unit is
//! started by hand (`systemctl restart`), so after a long life of rare deaths it waits the
//! longest time at once.

use std::fmt;
use std::time::Duration;

/// Waits before restarts that grow from `first` to `max` in `steps` steps, as systemd's
/// `RestartSec=`, `RestartSteps=` and `RestartMaxDelaySec=` do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RestartPolicy {
    /// The wait before the first restart (`RestartSec=`).
    pub first: Duration,
    /// In how many restarts the wait grows to `max` (`RestartSteps=`).
    pub steps: u32,
    /// The longest wait (`RestartMaxDelaySec=`).
    pub max: Duration,
    /// A run at least this long was healthy: the launcher starts from `first` again.
    pub healthy_run: Duration,
}

/// The gateway's restarts: 0.1 s, doubling each time, to at most 12.8 s.
pub const GATEWAY_RESTART: RestartPolicy = RestartPolicy {
    first: Duration::from_millis(100),
    steps: 7,
    max: Duration::from_millis(12_800),
    healthy_run: Duration::from_secs(30),
};

/// The ROS 2 node's restarts: always 2 s (a node started before the core's services exist
/// exits, and is started again once they are up).
pub const ROS2_RESTART: RestartPolicy = RestartPolicy {
    first: Duration::from_secs(2),
    steps: 0,
    max: Duration::from_secs(2),
    healthy_run: Duration::ZERO,
};

impl RestartPolicy {
    /// The wait before restart number `n` (1: the first one), in whole milliseconds, by
    /// systemd's formula: `first` for the first, then `first * (max / first) ^ ((n - 1) /
    /// steps)`, and `max` from restart `steps + 1` on.
    pub fn delay(&self, n: u32) -> Duration {
        if n <= 1 || self.steps == 0 || self.first.is_zero() || self.first >= self.max {
            return self.first;
        }
        if n > self.steps {
            return self.max;
        }
        let ratio = self.max.as_secs_f64() / self.first.as_secs_f64();
        let wait = self.first.as_secs_f64() * ratio.powf(f64::from(n - 1) / f64::from(self.steps));
        Duration::from_millis((wait * 1e3).round() as u64)
    }

    /// The lines of a systemd unit's `[Service]` section that give it this policy: only
    /// `RestartSec=` for a fixed wait (`steps` 0 or `first` at `max`).
    pub fn systemd_lines(&self) -> Vec<String> {
        let first = format!("RestartSec={}ms", self.first.as_millis());
        if self.steps == 0 || self.first >= self.max {
            return vec![first];
        }
        vec![
            first,
            format!("RestartSteps={}", self.steps),
            format!("RestartMaxDelaySec={}ms", self.max.as_millis()),
        ]
    }
}

impl fmt::Display for RestartPolicy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:?} growing in {} steps to {:?}, from {:?} again after {:?} of running",
            self.first, self.steps, self.max, self.first, self.healthy_run
        )
    }
}

#[cfg(test)]
mod tests;
