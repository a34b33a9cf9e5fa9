//! Percentiles of measured durations (pure, no I/O).
//!
//! Percentiles are nearest-rank: the p-th percentile of n sorted values is the value at rank
//! `ceil(p / 100 * n)` (1-based), so it is always one of the measured values, never an
//! interpolation.

use std::time::Duration;

/// The 1-based nearest rank of percentile `p` among `n` values (a product like 99.9 % of 1000
/// that floating point makes 999.0000000000001 is rank 999, not 1000).
fn rank_of(p: f64, n: u64) -> u64 {
    ((p / 100.0) * n as f64 - 1e-9).ceil().max(1.0) as u64
}

/// Nearest-rank percentile `p` (0 < p <= 100) of `sorted` (ascending); `None` when empty.
pub fn percentile<T: Copy>(sorted: &[T], p: f64) -> Option<T> {
    if sorted.is_empty() || !(p > 0.0 && p <= 100.0) {
        return None;
    }
    let n = sorted.len();
    let rank = rank_of(p, n as u64) as usize;
    Some(sorted[rank.clamp(1, n) - 1])
}

/// Summary of a set of durations [µs].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Summary {
    pub count: usize,
    pub p50_us: f64,
    pub p99_us: f64,
    pub p99_9_us: f64,
    pub max_us: f64,
    pub mean_us: f64,
}

impl Summary {
    /// The summary of `samples`; `None` when there are none.
    pub fn of(samples: &[Duration]) -> Option<Summary> {
        let mut us: Vec<f64> = samples.iter().map(|d| d.as_secs_f64() * 1e6).collect();
        Self::of_us(&mut us)
    }

    /// The summary of `us` [µs] (sorted in place); `None` when empty.
    pub fn of_us(us: &mut [f64]) -> Option<Summary> {
        if us.is_empty() {
            return None;
        }
        us.sort_by(f64::total_cmp);
        let mean_us = us.iter().sum::<f64>() / us.len() as f64;
        Some(Summary {
            count: us.len(),
            p50_us: percentile(us, 50.0)?,
            p99_us: percentile(us, 99.0)?,
            p99_9_us: percentile(us, 99.9)?,
            max_us: *us.last()?,
            mean_us,
        })
    }
}

/// A percentile read from a histogram of whole microseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HistFigure {
    /// The percentile lies in this bucket [µs].
    Us(u64),
    /// The percentile lies beyond the histogram's last bucket (`limit` µs).
    Beyond { limit: u64 },
}

/// Nearest-rank percentile `p` of a histogram: `buckets[i]` counts samples of `i` µs, and
/// `overflow` counts samples of `buckets.len()` µs or more. `None` when it holds no sample.
pub fn hist_percentile(buckets: &[u64], overflow: u64, p: f64) -> Option<HistFigure> {
    let total: u64 = buckets.iter().sum::<u64>() + overflow;
    if total == 0 || !(p > 0.0 && p <= 100.0) {
        return None;
    }
    let rank = rank_of(p, total).clamp(1, total);
    let mut seen = 0;
    for (us, n) in buckets.iter().enumerate() {
        seen += n;
        if seen >= rank {
            return Some(HistFigure::Us(us as u64));
        }
    }
    Some(HistFigure::Beyond {
        limit: buckets.len() as u64,
    })
}

#[cfg(test)]
mod tests;
