//! The time law of the path parameter: s goes from 0 to 1 at rest at both ends, within a
//! speed, acceleration and jerk bound that change along the path.
//!
//! The path is cut into at most [`MAX_SEGMENTS`] segments, each with its own bounds V, A, J
//! on ṡ, s̈, s⃛ ([`Segment`]). The law crosses each segment in three phases: a ramp from the
//! speed it enters with to a peak, a cruise at the peak, a ramp to the speed it leaves with.
//! A ramp changes the speed with jerk ±J (an acceleration plateau at A when it is reached)
//! and starts and ends without acceleration, so s̈ is continuous everywhere and s⃛ is 0 or
//! ±J of the segment it is in; without a jerk limit (J infinite) a ramp is a constant
//! acceleration A.
//!
//! The speeds where segments meet come from a backward pass (each at most what the segment
//! after it can slow down from within its length) and a forward pass (each at most what the
//! segment before it can reach), each at most both neighbours' V; each segment's peak is then
//! the largest at most its V whose two ramps fit its length. A ramp from v₀ to v₁ takes
//! T = |Δv|/A + A/J (or 2√(|Δv|/J) when it does not reach A) and covers (v₀ + v₁)·T/2.
//! Planning and sampling are allocation-free; sampling finds the segment by a binary search
//! (at most log₂ [`MAX_SEGMENTS`] + 1 steps). One segment entered and left at rest is the
//! double-S of `mcm-rt-core`'s joint moves (`trajectory::profile`) over the segment's length.

/// The most segments a path's time law has.
pub const MAX_SEGMENTS: usize = 64;

/// A piece of the path and the bounds the law keeps within it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Segment {
    /// Its length in s (> 0).
    pub length: f64,
    /// The bounds on ṡ [1/s], s̈ [1/s²] and s⃛ [1/s³] (> 0; the jerk may be infinite).
    pub v: f64,
    pub a: f64,
    pub j: f64,
}

/// A change of ṡ from `v0` to `v1`, starting and ending without acceleration.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Ramp {
    v0: f64,
    v1: f64,
    /// The peak |s̈| and the duration of each jerk phase (0: a constant acceleration).
    a: f64,
    t_j: f64,
    duration: f64,
}

impl Ramp {
    /// The fastest ramp within |s̈| ≤ `a_max`, |s⃛| ≤ `jerk` (infinite: no jerk limit).
    fn new(v0: f64, v1: f64, a_max: f64, jerk: f64) -> Ramp {
        let dv = (v1 - v0).abs();
        if dv == 0.0 {
            return Ramp {
                v0,
                v1,
                ..Ramp::default()
            };
        }
        let a = a_max.min((dv * jerk).sqrt());
        let t_j = if jerk.is_finite() { a / jerk } else { 0.0 };
        Ramp {
            v0,
            v1,
            a,
            t_j,
            duration: dv / a + t_j,
        }
    }

    fn distance(&self) -> f64 {
        (self.v0 + self.v1) / 2.0 * self.duration
    }

    /// (distance from the ramp's start, ṡ, s̈) at `tau` ∈ [0, duration].
    fn at(&self, tau: f64) -> (f64, f64, f64) {
        let (a, tj, big_t) = (self.a, self.t_j, self.duration);
        let tau = tau.clamp(0.0, big_t);
        let dv = (self.v1 - self.v0).abs();
        // The speed gained u, its rate and the distance it adds, as if starting from rest.
        let (dist, u, acc) = if tau < tj {
            (
                a * tau.powi(3) / (6.0 * tj),
                a * tau * tau / (2.0 * tj),
                a * tau / tj,
            )
        } else if tau <= big_t - tj {
            let m = tau - tj;
            (
                a * tj * tj / 6.0 + a * tj / 2.0 * m + a * m * m / 2.0,
                a * tj / 2.0 + a * m,
                a,
            )
        } else {
            let r = big_t - tau;
            (
                dv * big_t / 2.0 - (dv * r - a * r.powi(3) / (6.0 * tj)),
                dv - a * r * r / (2.0 * tj),
                a * r / tj,
            )
        };
        let sign = if self.v1 >= self.v0 { 1.0 } else { -1.0 };
        (self.v0 * tau + sign * dist, self.v0 + sign * u, sign * acc)
    }
}

/// The distance a ramp from `v0` to `v1` covers under `seg`'s bounds.
fn ramp_distance(v0: f64, v1: f64, seg: &Segment) -> f64 {
    Ramp::new(v0, v1, seg.a, seg.j).distance()
}

/// The largest v in [`from`, `cap`] with `fits(v)`, `fits` holding at `from` and monotonic.
fn largest(from: f64, cap: f64, fits: impl Fn(f64) -> bool) -> f64 {
    if cap <= from || fits(cap) {
        return cap.max(from);
    }
    let (mut lo, mut hi) = (from, cap);
    for _ in 0..60 {
        let mid = (lo + hi) / 2.0;
        if fits(mid) { lo = mid } else { hi = mid }
    }
    lo
}

/// How one segment is crossed.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Crossing {
    /// Where and when it starts.
    s0: f64,
    t0: f64,
    head: Ramp,
    /// The cruise's speed (the peak) and duration.
    peak: f64,
    cruise: f64,
    tail: Ramp,
    /// The segment and its bounds.
    segment: Segment,
}

impl Crossing {
    fn duration(&self) -> f64 {
        self.head.duration + self.cruise + self.tail.duration
    }

    /// (s, ṡ, s̈) at `tau` after its start, s within the segment.
    fn at(&self, tau: f64) -> (f64, f64, f64) {
        let (ds, v, a) = if tau <= self.head.duration {
            self.head.at(tau)
        } else if tau <= self.head.duration + self.cruise {
            let m = tau - self.head.duration;
            (self.head.distance() + self.peak * m, self.peak, 0.0)
        } else {
            let (ds, v, a) = self.tail.at(tau - self.head.duration - self.cruise);
            (self.segment.length - self.tail.distance() + ds, v, a)
        };
        (self.s0 + ds.clamp(0.0, self.segment.length), v, a)
    }
}

/// A rest-to-rest law of s from 0 to 1 through its segments. Plain data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PathProfile {
    crossings: [Crossing; MAX_SEGMENTS],
    count: usize,
    duration: f64,
}

impl Default for PathProfile {
    fn default() -> Self {
        PathProfile {
            crossings: [Crossing {
                s0: 0.0,
                t0: 0.0,
                head: Ramp::default(),
                peak: 0.0,
                cruise: 0.0,
                tail: Ramp::default(),
                segment: Segment {
                    length: 0.0,
                    v: 0.0,
                    a: 0.0,
                    j: 0.0,
                },
            }; MAX_SEGMENTS],
            count: 0,
            duration: 0.0,
        }
    }
}

impl PathProfile {
    /// The law through `segments` (in order along the path, at most [`MAX_SEGMENTS`], their
    /// lengths summing to 1): the module's doc. No segment: the zero law (duration 0).
    pub fn new(segments: &[Segment]) -> PathProfile {
        let segments = &segments[..segments.len().min(MAX_SEGMENTS)];
        let n = segments.len();
        let mut profile = PathProfile::default();
        if n == 0 {
            return profile;
        }
        // The speeds where segment i starts (joints[i]) and ends (joints[i + 1]).
        let mut joints = [0.0; MAX_SEGMENTS + 1];
        for i in 1..n {
            joints[i] = segments[i - 1].v.min(segments[i].v);
        }
        for i in (0..n).rev() {
            let (seg, exit) = (&segments[i], joints[i + 1]);
            joints[i] = largest(exit, joints[i], |v| {
                ramp_distance(v, exit, seg) <= seg.length
            })
            .min(joints[i]);
        }
        for i in 0..n {
            let (seg, entry) = (&segments[i], joints[i]);
            joints[i + 1] = largest(entry, joints[i + 1], |v| {
                ramp_distance(entry, v, seg) <= seg.length
            })
            .min(joints[i + 1]);
        }
        let (mut s0, mut t0) = (0.0, 0.0);
        for (i, seg) in segments.iter().enumerate() {
            let (entry, exit) = (joints[i], joints[i + 1]);
            let both = |v: f64| ramp_distance(entry, v, seg) + ramp_distance(v, exit, seg);
            let peak = largest(entry.max(exit), seg.v, |v| both(v) <= seg.length);
            let head = Ramp::new(entry, peak, seg.a, seg.j);
            let tail = Ramp::new(peak, exit, seg.a, seg.j);
            let rest = (seg.length - head.distance() - tail.distance()).max(0.0);
            let crossing = Crossing {
                s0,
                t0,
                head,
                peak,
                cruise: if peak > 0.0 { rest / peak } else { 0.0 },
                tail,
                segment: *seg,
            };
            s0 += seg.length;
            t0 += crossing.duration();
            profile.crossings[i] = crossing;
        }
        profile.count = n;
        profile.duration = t0;
        profile
    }

    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// (s, ds/dt, d²s/dt²) at time `t` [s]: (0, 0, 0) before the start (and for NaN),
    /// exactly (1, 0, 0) from the end on.
    pub fn sample(&self, t: f64) -> (f64, f64, f64) {
        if t.is_nan() || t <= 0.0 || self.count == 0 {
            return (0.0, 0.0, 0.0);
        }
        if t >= self.duration {
            return (1.0, 0.0, 0.0);
        }
        let crossings = &self.crossings[..self.count];
        // The last crossing starting at or before t (the first starts at 0).
        let i = crossings.partition_point(|c| c.t0 <= t).max(1) - 1;
        let (s, v, a) = crossings[i].at(t - crossings[i].t0);
        (s.clamp(0.0, 1.0), v, a)
    }

    /// The segment whose bounds hold at `s` (tests check the law against them).
    #[cfg(test)]
    pub fn segment_at(&self, s: f64) -> Segment {
        let crossings = &self.crossings[..self.count];
        let i = crossings.partition_point(|c| c.s0 <= s).max(1) - 1;
        crossings[i].segment
    }

    /// The law of one segment with the smallest bounds of all: one pace for the whole path.
    #[cfg(test)]
    pub fn uniform(&self) -> PathProfile {
        let crossings = &self.crossings[..self.count];
        let least = |f: fn(&Segment) -> f64| {
            crossings
                .iter()
                .map(|c| f(&c.segment))
                .fold(f64::INFINITY, f64::min)
        };
        PathProfile::new(&[Segment {
            length: 1.0,
            v: least(|g| g.v),
            a: least(|g| g.a),
            j: least(|g| g.j),
        }])
    }

    /// The number of segments.
    #[cfg(test)]
    pub fn segments(&self) -> usize {
        self.count
    }
}
