//! One axis's trajectory as a short chain of constant-jerk segments ([`AxisPlan`]), and the
//! builder the planners use to chain brakes, velocity ramps and cruises into one. Building,
//! sampling and the closed-form checks (position range, peak velocity and acceleration) are
//! O(number of segments), allocation- and panic-free: they may run **inside the cycle**.
//!
//! A segment starts at a given state (p, v, a) and runs at a constant jerk; position and
//! velocity are integrated from segment to segment, so they are continuous. The acceleration
//! is continuous too, except where a plan without a jerk limit switches it (trapezoids).
//! From `duration()` on the plan holds its target exactly, at rest.

use super::{AxisLimits, PlanError};

/// Most segments one plan needs: a brake (3), a ramp (3), a cruise (1), a ramp (3), plus a
/// second ramp-cruise-ramp when the axis first has to come back (see [`super::online`]).
pub const MAX_SEGMENTS: usize = 14;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Segment {
    /// Start time (s since the plan started).
    t0: f64,
    p: f64,
    v: f64,
    a: f64,
    j: f64,
}

impl Segment {
    fn at(&self, tau: f64) -> (f64, f64, f64) {
        let (v, a, j) = (self.v, self.a, self.j);
        (
            self.p + tau * (v + tau * (a / 2.0 + tau * j / 6.0)),
            v + tau * (a + tau * j / 2.0),
            a + j * tau,
        )
    }
}

/// A 1-D trajectory of up to [`MAX_SEGMENTS`] constant-jerk segments ending at rest on its
/// target. `Copy`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisPlan {
    segs: [Segment; MAX_SEGMENTS],
    n: usize,
    duration: f64,
    target: f64,
    /// The state the plan starts from (without a jerk limit the first segment may already
    /// have switched the acceleration).
    start: (f64, f64, f64),
}

impl AxisPlan {
    /// An axis that stays at `position`, at rest.
    pub fn hold(position: f64) -> AxisPlan {
        AxisPlan {
            segs: [Segment::default(); MAX_SEGMENTS],
            n: 0,
            duration: 0.0,
            target: position,
            start: (position, 0.0, 0.0),
        }
    }

    /// Duration (s); 0 for a held axis.
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// Where the plan ends, at rest (rad).
    pub fn target(&self) -> f64 {
        self.target
    }

    /// The state (p, v, a) `t` seconds after the start; before 0 (or NaN) the start state,
    /// from `duration()` on exactly (target, 0, 0).
    pub fn sample(&self, t: f64) -> (f64, f64, f64) {
        if t.is_nan() || t <= 0.0 {
            return self.start;
        }
        if self.n == 0 || t >= self.duration {
            return (self.target, 0.0, 0.0);
        }
        let mut k = self.n - 1;
        while k > 0 && self.segs[k].t0 > t {
            k -= 1;
        }
        let s = &self.segs[k];
        s.at(t - s.t0)
    }

    /// End time of segment `k`.
    fn end(&self, k: usize) -> f64 {
        if k + 1 < self.n {
            self.segs[k + 1].t0
        } else {
            self.duration
        }
    }

    /// The lowest and highest position the plan passes through (closed form: segment ends and
    /// the velocity's zeros inside each segment).
    pub fn position_range(&self) -> (f64, f64) {
        let (mut lo, mut hi) = (self.target.min(self.start.0), self.target.max(self.start.0));
        for k in 0..self.n {
            let s = &self.segs[k];
            let len = self.end(k) - s.t0;
            let mut see = |tau: f64| {
                if tau >= 0.0 && tau <= len {
                    let p = s.at(tau).0;
                    lo = lo.min(p);
                    hi = hi.max(p);
                }
            };
            see(0.0);
            see(len);
            for tau in quadratic_roots(s.j / 2.0, s.a, s.v) {
                see(tau);
            }
        }
        (lo, hi)
    }

    /// Peak |velocity| (closed form: segment ends and the acceleration's zero in each).
    pub fn peak_velocity(&self) -> f64 {
        let mut peak = self.start.1.abs();
        for k in 0..self.n {
            let s = &self.segs[k];
            let len = self.end(k) - s.t0;
            peak = peak.max(s.v.abs()).max(s.at(len).1.abs());
            if s.j != 0.0 {
                let tau = -s.a / s.j;
                if tau > 0.0 && tau < len {
                    peak = peak.max(s.at(tau).1.abs());
                }
            }
        }
        peak
    }

    /// Peak |acceleration| (linear within a segment: its ends).
    pub fn peak_acceleration(&self) -> f64 {
        let mut peak = self.start.2.abs();
        for k in 0..self.n {
            let s = &self.segs[k];
            let len = self.end(k) - s.t0;
            peak = peak.max(s.a.abs()).max(s.at(len).2.abs());
        }
        peak
    }

    /// Segment start times and the end (for tests that probe around every switch).
    pub fn switch_times(&self) -> impl Iterator<Item = f64> + '_ {
        self.segs[..self.n]
            .iter()
            .map(|s| s.t0)
            .chain(core::iter::once(self.duration))
    }
}

/// Real roots of c2·x² + c1·x + c0 (none, one or two; NaN slots are skipped by callers'
/// range checks).
fn quadratic_roots(c2: f64, c1: f64, c0: f64) -> [f64; 2] {
    if c2 == 0.0 {
        return if c1 == 0.0 {
            [f64::NAN; 2]
        } else {
            [-c0 / c1, f64::NAN]
        };
    }
    let disc = c1 * c1 - 4.0 * c2 * c0;
    if disc < 0.0 {
        return [f64::NAN; 2];
    }
    let r = disc.sqrt();
    [(-c1 - r) / (2.0 * c2), (-c1 + r) / (2.0 * c2)]
}

/// Time to change the velocity by `dv` (≥ 0) from a = 0 back to a = 0 under `lim` (T_acc of
/// [`super::profile`]'s closed form: dv/A without a jerk limit).
pub fn ramp_time(dv: f64, lim: &AxisLimits) -> f64 {
    let a = lim.acceleration;
    match lim.jerk {
        None => dv / a,
        Some(j) if dv * j >= a * a => dv / a + a / j,
        Some(j) => 2.0 * (dv / j).sqrt(),
    }
}

/// Distance covered by a velocity ramp from `va` to `vb` (the profile is point-symmetric, so
/// the mean velocity is (va + vb)/2).
pub fn ramp_distance(va: f64, vb: f64, lim: &AxisLimits) -> f64 {
    (va + vb) / 2.0 * ramp_time((vb - va).abs(), lim)
}

/// Chains segments from a start state. A push of zero (or negative, or NaN) duration is
/// skipped; too many segments make [`Builder::finish`] fail.
#[derive(Clone, Copy, Debug)]
pub struct Builder {
    plan: AxisPlan,
    p: f64,
    v: f64,
    a: f64,
    t: f64,
    p0: f64,
    overflow: bool,
}

impl Builder {
    pub fn new(p: f64, v: f64, a: f64) -> Builder {
        Builder {
            plan: AxisPlan {
                start: (p, v, a),
                ..AxisPlan::hold(p)
            },
            p,
            v,
            a,
            t: 0.0,
            p0: p,
            overflow: false,
        }
    }

    /// The state reached so far (p, v, a).
    pub fn state(&self) -> (f64, f64, f64) {
        (self.p, self.v, self.a)
    }

    /// Switch the acceleration (only for plans without a jerk limit, or to remove rounding).
    pub fn set_acceleration(&mut self, a: f64) {
        self.a = a;
    }

    /// Snap the velocity to `v` after a ramp (removes rounding; no physical effect).
    pub fn set_velocity(&mut self, v: f64) {
        self.v = v;
    }

    /// Run for `duration` at jerk `j` from the current state.
    pub fn push(&mut self, duration: f64, j: f64) {
        if duration.is_nan() || duration <= 0.0 {
            return;
        }
        if self.plan.n == MAX_SEGMENTS {
            self.overflow = true;
            return;
        }
        let seg = Segment {
            t0: self.t,
            p: self.p,
            v: self.v,
            a: self.a,
            j,
        };
        self.plan.segs[self.plan.n] = seg;
        self.plan.n += 1;
        (self.p, self.v, self.a) = seg.at(duration);
        self.t += duration;
    }

    /// Ramp the velocity from the current one (at a = 0) to `vb` under `lim`, ending at a = 0.
    pub fn ramp(&mut self, vb: f64, lim: &AxisLimits) {
        let dv = vb - self.v;
        let (m, s) = (dv.abs(), dv.signum());
        if m == 0.0 {
            return;
        }
        let a_max = lim.acceleration;
        match lim.jerk {
            None => {
                self.a = s * a_max;
                self.push(m / a_max, 0.0);
            }
            Some(j) if m * j >= a_max * a_max => {
                let tj = a_max / j;
                self.push(tj, s * j);
                self.a = s * a_max;
                self.push(m / a_max - tj, 0.0);
                self.push(tj, -s * j);
            }
            Some(j) => {
                let tj = (m / j).sqrt();
                self.push(tj, s * j);
                self.push(tj, -s * j);
            }
        }
        self.a = 0.0;
        self.v = vb;
    }

    /// Cruise at the current velocity (a = 0) for `duration`.
    pub fn cruise(&mut self, duration: f64) {
        self.a = 0.0;
        self.push(duration, 0.0);
    }

    /// The plan, ending on `target` at rest. Fails when the segments do not fit or do not end
    /// (within rounding) on the target at rest.
    pub fn finish(self, target: f64) -> Result<AxisPlan, PlanError> {
        let scale = 1.0 + target.abs() + self.p0.abs();
        let off = (self.p - target).abs();
        if self.overflow || !self.t.is_finite() || off.is_nan() || off > 1e-9 * scale {
            return Err(PlanError::Numeric {
                distance: target - self.p0,
            });
        }
        let mut plan = self.plan;
        plan.duration = self.t;
        plan.target = target;
        Ok(plan)
    }
}
