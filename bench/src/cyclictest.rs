//! `cyclictest` (rt-tests) at the cycle's period, priority and CPU, and the parsing of its
//! histogram output (`-q -h US`).

use crate::error::BenchError;
use crate::stats::{HistFigure, hist_percentile};
use std::process::{Child, Command, Stdio};

/// The histogram range asked of cyclictest [µs]; latencies above it are counted as overflows
/// (the maximum is still reported exactly).
pub const HIST_LIMIT_US: u64 = 20_000;

/// What one cyclictest run measured.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CyclicResult {
    /// `buckets[i]`: samples of `i` µs.
    pub buckets: Vec<u64>,
    pub overflows: u64,
    pub total: u64,
    pub max_us: u64,
}

impl CyclicResult {
    pub fn percentile(&self, p: f64) -> Option<HistFigure> {
        hist_percentile(&self.buckets, self.overflows, p)
    }
}

/// Parse the output of `cyclictest -q -h US` with one thread.
pub fn parse(out: &str) -> Result<CyclicResult, BenchError> {
    let bad = |what: &str| BenchError::Cyclictest(format!("{what} in its output:\n{out}"));
    let mut buckets = Vec::new();
    let mut overflows = None;
    let mut total = None;
    let mut max_us = None;
    for line in out.lines() {
        let line = line.trim();
        if let Some(rest) = line.strip_prefix('#') {
            let (key, value) = match rest.split_once(':') {
                Some((k, v)) => (k.trim(), v.trim()),
                None => continue,
            };
            let first = value.split_whitespace().next().and_then(|v| v.parse().ok());
            match key {
                "Total" => total = first,
                "Max Latencies" => max_us = first,
                "Histogram Overflows" => overflows = first,
                _ => {}
            }
            continue;
        }
        let mut cols = line.split_whitespace();
        let (Some(us), Some(n)) = (cols.next(), cols.next()) else {
            continue;
        };
        let (Ok(us), Ok(n)) = (us.parse::<usize>(), n.parse::<u64>()) else {
            continue;
        };
        if us != buckets.len() {
            return Err(bad(&format!("histogram row {us} out of order")));
        }
        buckets.push(n);
    }
    let total = total.ok_or_else(|| bad("no `# Total:` line"))?;
    let overflows = overflows.ok_or_else(|| bad("no `# Histogram Overflows:` line"))?;
    let max_us = max_us.ok_or_else(|| bad("no `# Max Latencies:` line"))?;
    if buckets.is_empty() {
        return Err(bad("no histogram rows"));
    }
    Ok(CyclicResult {
        buckets,
        overflows,
        total,
        max_us,
    })
}

/// A cyclictest run in progress.
pub struct Cyclictest {
    child: Child,
}

impl Cyclictest {
    /// Start `cyclictest` at SCHED_FIFO `prio` on `cpu`, every `period_us`, for `secs`.
    pub fn start(prio: u8, cpu: usize, period_us: u64, secs: u64) -> Result<Self, BenchError> {
        let child = Command::new("cyclictest")
            .args([
                format!("-p{prio}"),
                format!("-a{cpu}"),
                format!("-i{period_us}"),
                "-m".into(),
                "-q".into(),
                format!("-D{secs}"),
                format!("-h{HIST_LIMIT_US}"),
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| {
                BenchError::Cyclictest(format!(
                    "cannot start `cyclictest` ({e}); install rt-tests (scripts/bench.sh does \
                     it with apt-get) or pass --no-cyclictest"
                ))
            })?;
        Ok(Cyclictest { child })
    }

    /// Wait for the run to end and parse its histogram.
    pub fn finish(self) -> Result<CyclicResult, BenchError> {
        let out = self
            .child
            .wait_with_output()
            .map_err(|e| BenchError::Cyclictest(format!("waiting for cyclictest: {e}")))?;
        if !out.status.success() {
            return Err(BenchError::Cyclictest(format!(
                "cyclictest exited with {}: {}",
                out.status,
                String::from_utf8_lossy(&out.stderr).trim()
            )));
        }
        parse(&String::from_utf8_lossy(&out.stdout))
    }
}

#[cfg(test)]
mod tests;
