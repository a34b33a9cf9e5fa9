//! `builtin_interfaces`: `Time` and `Duration`.

use serde::{Deserialize, Serialize};

/// `builtin_interfaces/msg/Time`: seconds and nanoseconds since the epoch of the clock.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Time {
    pub sec: i32,
    pub nanosec: u32,
}

impl Time {
    /// `CLOCK_REALTIME` now: ROS 2's system time, what rclpy's `get_clock().now()` reads.
    pub fn now() -> Time {
        let d = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap_or_default();
        Time {
            sec: d.as_secs() as i32,
            nanosec: d.subsec_nanos(),
        }
    }

    /// Nanoseconds since the epoch.
    pub fn as_nanos(self) -> i64 {
        i64::from(self.sec) * 1_000_000_000 + i64::from(self.nanosec)
    }

    /// From nanoseconds since the epoch (`nanosec` in `0..1e9`, as ROS keeps it).
    pub fn from_nanos(ns: i64) -> Time {
        Time {
            sec: ns.div_euclid(1_000_000_000) as i32,
            nanosec: ns.rem_euclid(1_000_000_000) as u32,
        }
    }

    /// This time shifted by `s` seconds.
    pub fn plus_secs(self, s: f64) -> Time {
        Time::from_nanos(self.as_nanos() + (s * 1e9) as i64)
    }
}

/// `builtin_interfaces/msg/Duration`. A negative duration has a negative `sec` and a
/// `nanosec` in `0..1e9` (ROS's normal form).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Duration {
    pub sec: i32,
    pub nanosec: u32,
}

impl Duration {
    /// In seconds.
    pub fn as_secs_f64(self) -> f64 {
        f64::from(self.sec) + f64::from(self.nanosec) * 1e-9
    }

    /// From seconds (rounded to the nanosecond).
    pub fn from_secs_f64(s: f64) -> Duration {
        let ns = (s * 1e9).round() as i64;
        Duration {
            sec: ns.div_euclid(1_000_000_000) as i32,
            nanosec: ns.rem_euclid(1_000_000_000) as u32,
        }
    }
}
