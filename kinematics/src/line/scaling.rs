//! The time law's bounds along the path: for each checked interval the largest ds/dt (V),
//! d²s/dt² (A) and d³s/dt³ (J) that keep the TCP within the request and every axis within its
//! limits there; gathered into at most [`MAX_SEGMENTS`] segments for [`PathProfile`].
//!
//! Along the path q̇ = q′ṡ, q̈ = q″ṡ² + q′s̈ and q⃛ = q‴ṡ³ + 3q″ṡs̈ + q′s⃛ (′: d/ds). With an
//! interval's bounds Q1, Q2, Q3 of |q′|, |q″|, |q‴| ([`super::check`]) and |ṡ| ≤ V, |s̈| ≤ A,
//! |s⃛| ≤ J there, each axis stays within its velocity v, acceleration a and jerk j when
//!
//! - Q1·V ≤ v;
//! - Q2·V² ≤ a/2 and Q1·A ≤ a − Q2·V² (half the acceleration is kept for the path's bend);
//! - Q3·V³ ≤ j/4, 3·Q2·V·A ≤ j/4 and Q1·J ≤ j − Q3·V³ − 3·Q2·V·A.
//!
//! The TCP's speed is |p₁ − p₀|·ṡ and its acceleration |p₁ − p₀|·s̈, its angular speed and
//! acceleration the turn's angle times ṡ and s̈: V and A are also held to the request (the
//! angular ones to the request divided by [`ROTATION_RADIUS_M`]). V is chosen first, the
//! largest the velocity rows allow, then A, then J (infinite when no axis has a jerk limit).
//!
//! An interval's bounds are the smallest of its own and its two neighbours' (the derivative
//! estimates are differences over neighbouring points). Neighbouring intervals form one
//! segment with the smallest V, A and J of its intervals as long as crossing it at its V
//! takes at most half a jerk phase A/J (or half an interval's crossing, without a jerk limit)
//! longer than crossing each interval at its own V would: the law comes to zero acceleration
//! where segments meet, which costs about that much. Should that give more than [`MAX_SEGMENTS`],
//! the segments are merged again allowing twice the loss, until they fit (a path whose pace
//! changes little is one segment: the law of one double-S).

use super::check::Bounds;
use super::profile::{MAX_SEGMENTS, PathProfile, Segment};
use super::{JointLimits, ROTATION_RADIUS_M};
use crate::N;
use nalgebra::Vector6;

/// A segment and the time its intervals take each at its own V (Σ h/V).
#[derive(Clone, Copy)]
struct Gathered {
    segment: Segment,
    own: f64,
}

/// The bounds of the intervals of a path, in order, gathered into segments.
pub(super) struct Pace {
    limits: JointLimits,
    /// The request's bounds on ṡ and s̈.
    v_request: f64,
    a_request: f64,
    /// The length of an interval in s.
    h: f64,
    /// The raw bounds of the two intervals before the next (the neighbours' minimum).
    before: Option<Segment>,
    current: Option<Segment>,
    gathered: [Gathered; MAX_SEGMENTS],
    count: usize,
    /// The loss allowed, in jerk phases (the module's doc): 0.5, doubled when the segments
    /// do not fit.
    allowance: f64,
}

impl Pace {
    /// The pace of a path with derivative `twist` (per unit s) cut into intervals `h` long,
    /// for the requested TCP `velocity` [m/s] and `acceleration` [m/s²]. `None` when the path
    /// has no displacement and no turn (nothing to move).
    pub fn new(
        limits: &JointLimits,
        velocity: f64,
        acceleration: f64,
        twist: &Vector6<f64>,
        h: f64,
    ) -> Option<Pace> {
        let length = twist.fixed_rows::<3>(0).norm();
        let angle = twist.fixed_rows::<3>(3).norm();
        let (mut v, mut a) = (f64::INFINITY, f64::INFINITY);
        if length > 0.0 {
            v = v.min(velocity / length);
            a = a.min(acceleration / length);
        }
        if angle > 0.0 {
            v = v.min(velocity / ROTATION_RADIUS_M / angle);
            a = a.min(acceleration / ROTATION_RADIUS_M / angle);
        }
        (v.is_finite() && a.is_finite()).then_some(Pace {
            limits: *limits,
            v_request: v,
            a_request: a,
            h,
            before: None,
            current: None,
            gathered: [Gathered {
                segment: Segment {
                    length: 0.0,
                    v,
                    a,
                    j: f64::INFINITY,
                },
                own: 0.0,
            }; MAX_SEGMENTS],
            count: 0,
            allowance: 0.5,
        })
    }

    /// The next interval's bounds of |q′|, |q″|, |q‴|.
    pub fn push(&mut self, bounds: &Bounds) {
        let raw = self.bounds_of(bounds);
        if let Some(current) = self.current {
            let before = self.before.unwrap_or(current);
            self.gather(lowest(&lowest(&before, &current), &raw));
            self.before = Some(current);
        }
        self.current = Some(raw);
    }

    /// The time law through the intervals pushed.
    pub fn profile(mut self) -> PathProfile {
        if let Some(current) = self.current {
            let before = self.before.unwrap_or(current);
            self.gather(lowest(&before, &current));
        }
        let mut segments = [self.gathered[0].segment; MAX_SEGMENTS];
        for (s, g) in segments.iter_mut().zip(&self.gathered[..self.count]) {
            *s = g.segment;
        }
        PathProfile::new(&segments[..self.count])
    }

    /// V, A, J of one interval (the module's doc), its length `h`.
    fn bounds_of(&self, bounds: &Bounds) -> Segment {
        let limits = &self.limits;
        let (mut v, mut a) = (self.v_request, self.a_request);
        let Bounds {
            rate: q1,
            curvature: q2,
            third: q3,
        } = *bounds;
        for i in 0..N {
            if q1[i] > 0.0 {
                v = v.min(limits.velocity[i] / q1[i]);
            }
            if q2[i] > 0.0 {
                v = v.min((limits.acceleration[i] / (2.0 * q2[i])).sqrt());
            }
            if let Some(j) = limits.jerk[i]
                && q3[i] > 0.0
            {
                v = v.min((j / (4.0 * q3[i])).cbrt());
            }
        }
        for i in 0..N {
            if q1[i] > 0.0 {
                a = a.min((limits.acceleration[i] - q2[i] * v * v) / q1[i]);
            }
            if let Some(j) = limits.jerk[i]
                && q2[i] > 0.0
            {
                a = a.min(j / (12.0 * q2[i] * v));
            }
        }
        let mut jerk = f64::INFINITY;
        for i in 0..N {
            if let Some(j) = limits.jerk[i]
                && q1[i] > 0.0
            {
                jerk = jerk.min((j - q3[i] * v * v * v - 3.0 * q2[i] * v * a) / q1[i]);
            }
        }
        Segment {
            length: self.h,
            v,
            a,
            j: jerk,
        }
    }

    /// Add one interval's bounds to the last segment, or start a new one.
    fn gather(&mut self, interval: Segment) {
        let next = Gathered {
            segment: interval,
            own: interval.length / interval.v,
        };
        let joined = |pace: &Pace| {
            let last = pace.gathered[pace.count.checked_sub(1)?];
            merged(&last, &next, pace.allowance)
        };
        if self.count == MAX_SEGMENTS && joined(self).is_none() {
            self.regather();
        }
        match joined(self) {
            Some(m) => self.gathered[self.count - 1] = m,
            None => {
                self.gathered[self.count] = next;
                self.count += 1;
            }
        }
    }

    /// Double the allowance and merge the segments gathered so far again, until one is free.
    fn regather(&mut self) {
        while self.count == MAX_SEGMENTS {
            self.allowance *= 2.0;
            let mut count = 1;
            for k in 1..self.count {
                let (last, next) = (self.gathered[count - 1], self.gathered[k]);
                match merged(&last, &next, self.allowance) {
                    Some(m) => self.gathered[count - 1] = m,
                    None => {
                        self.gathered[count] = next;
                        count += 1;
                    }
                }
            }
            self.count = count;
        }
    }
}

/// `last` and `next` as one segment, if crossing it at its V loses at most `allowance` jerk
/// phases (or intervals' crossings, without a jerk limit) against each interval at its own.
fn merged(last: &Gathered, next: &Gathered, allowance: f64) -> Option<Gathered> {
    let segment = Segment {
        length: last.segment.length + next.segment.length,
        ..lowest(&last.segment, &next.segment)
    };
    let own = last.own + next.own;
    let phase = if segment.j.is_finite() {
        segment.a / segment.j
    } else {
        next.own
    };
    (segment.length / segment.v - own <= allowance * phase).then_some(Gathered { segment, own })
}

/// The smaller of each bound (the first's length).
fn lowest(x: &Segment, y: &Segment) -> Segment {
    Segment {
        length: x.length,
        v: x.v.min(y.v),
        a: x.a.min(y.a),
        j: x.j.min(y.j),
    }
}
