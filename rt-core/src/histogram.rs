//! A non-allocating latency histogram for the cycle's wake-up latency and work time.
//!
//! Runs inside the cycle: `record` is a few integer operations on a fixed array.
//!
//! Buckets are logarithmic with 8 sub-buckets per power of two (relative error below 12.5 %),
//! covering 0 ns to about 120 s; larger values land in the last bucket.
//!
//! ```
//! let mut h = mcm_rt_core::histogram::Histogram::new();
//! for ns in [1_000, 2_000, 3_000, 50_000] { h.record(ns); }
//! assert_eq!(h.count(), 4);
//! assert_eq!(h.max(), 50_000);
//! assert!(h.percentile(0.5) >= 1_000 && h.percentile(0.5) <= 2_250);
//! ```

const SUB_BITS: u32 = 3;
const SUB: usize = 1 << SUB_BITS;
const GROUPS: usize = 35;
const BUCKETS: usize = GROUPS * SUB;

/// Fixed-size log-linear histogram of nanosecond values.
#[derive(Clone)]
pub struct Histogram {
    counts: [u64; BUCKETS],
    count: u64,
    max: u64,
}

impl Default for Histogram {
    fn default() -> Self {
        Self::new()
    }
}

impl Histogram {
    pub const fn new() -> Self {
        Self {
            counts: [0; BUCKETS],
            count: 0,
            max: 0,
        }
    }

    fn index(v: u64) -> usize {
        if v < SUB as u64 {
            return v as usize;
        }
        let group = 63 - v.leading_zeros() - SUB_BITS + 1; // >= 1
        let sub = (v >> (group - 1)) as usize & (SUB - 1);
        ((group as usize) * SUB + sub).min(BUCKETS - 1)
    }

    /// Upper bound of the values that land in bucket `i` (the last bucket takes everything
    /// larger).
    fn upper(i: usize) -> u64 {
        if i == BUCKETS - 1 {
            return u64::MAX;
        }
        let group = i / SUB;
        let sub = (i % SUB) as u64;
        if group == 0 {
            return sub;
        }
        let shift = group as u32 - 1;
        ((SUB as u64 + sub + 1) << shift) - 1
    }

    /// Record one value [ns].
    #[inline]
    pub fn record(&mut self, ns: u64) {
        self.counts[Self::index(ns)] += 1;
        self.count += 1;
        self.max = self.max.max(ns);
    }

    pub fn count(&self) -> u64 {
        self.count
    }

    pub fn max(&self) -> u64 {
        self.max
    }

    /// The value below which a fraction `p` (0..=1) of the records lie, as the upper bound of
    /// its bucket (never above the maximum seen). 0 when empty.
    pub fn percentile(&self, p: f64) -> u64 {
        if self.count == 0 {
            return 0;
        }
        let rank = ((p.clamp(0.0, 1.0) * self.count as f64).ceil() as u64).max(1);
        let mut seen = 0;
        for (i, c) in self.counts.iter().enumerate() {
            seen += c;
            if seen >= rank {
                return Self::upper(i).min(self.max);
            }
        }
        self.max
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn empty_is_zero() {
        let h = Histogram::new();
        assert_eq!(h.percentile(0.99), 0);
        assert_eq!(h.count(), 0);
    }

    #[test]
    fn percentiles_of_a_uniform_spread() {
        let mut h = Histogram::new();
        for v in 1..=1000u64 {
            h.record(v * 1000);
        }
        let p50 = h.percentile(0.5);
        let p99 = h.percentile(0.99);
        assert!((500_000..=563_000).contains(&p50), "p50 {p50}");
        assert!((990_000..=1_000_000).contains(&p99), "p99 {p99}");
        assert_eq!(h.percentile(1.0), 1_000_000);
    }

    #[test]
    fn huge_values_saturate_the_last_bucket() {
        let mut h = Histogram::new();
        h.record(u64::MAX);
        assert_eq!(h.max(), u64::MAX);
        assert_eq!(h.percentile(0.5), u64::MAX);
    }

    proptest! {
        #[test]
        fn bucket_bounds_contain_the_value(v in 0u64..(15u64 << 33)) {
            let i = Histogram::index(v);
            prop_assert!(v <= Histogram::upper(i), "v {} upper {}", v, Histogram::upper(i));
            if i > 0 {
                prop_assert!(v > Histogram::upper(i - 1));
            }
            // relative error of the bucket bound below 12.5 %
            prop_assert!((Histogram::upper(i) - v) as f64 <= v as f64 * 0.125 + 1.0);
        }
    }
}
