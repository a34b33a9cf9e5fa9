//! Cubic Hermite PVT segments: how the points of `pvt_points` are interpolated
//! (docs/protocol.md, "pvt_points"). Construction, sampling and checking are O(1), allocation-
//! and panic-free: all may run **inside the cycle**.
//!
//! A segment joins (p0, v0) at τ = 0 to (p1, v1) at τ = dt:
//! p(τ) = p0 + v0·τ + c2·τ² + c3·τ³, where p(0) = p0 and p'(0) = v0 hold by construction and
//! p(dt) = p1, p'(dt) = v1 give c2 = (3(p1−p0)/dt − 2v0 − v1)/dt and
//! c3 = (2(p0−p1)/dt + v0 + v1)/dt². Consecutive segments share their knot (p, v), so position
//! and velocity are continuous; acceleration may jump at a knot.
//!
//! [`Hermite::check`] validates a segment in closed form before it is queued: positions at
//! both ends and at the interior extrema (roots of v(τ) = 0), |v| at both ends and at the
//! interior extremum τ* = −c2/(3c3), |a| at both ends (a is linear in τ). Jerk (6·c3, constant
//! per segment) is not checked, because a Hermite segment's jerk mostly reflects rounding in the
//! client's points; read it with [`Hermite::jerk`] if needed. Limits are accepted up to a
//! tolerance of [`CHECK_TOLERANCE`] (relative for v and a, rad for positions), so points exactly
//! at a limit pass after unit conversion.
//!
//! ```
//! use mcm_rt_core::trajectory::{AxisLimits, Hermite};
//! let seg = Hermite::new(0.98, 12.0, 0.99, 0.0, 0.01); // overshoots between its points
//! let lim = AxisLimits { velocity: 20.0, acceleration: 1e4, jerk: None };
//! assert!(seg.check(-1.0, 1.0, lim).is_err());
//! assert!(seg.check(-1.0, 1.01, lim).is_ok());
//! ```

use super::{AxisLimits, JointSample, PvtPoint, PvtSegmentError, SegmentError};
use mcm_shared::NUM_AXES;

/// Tolerance of [`Hermite::check`]: relative for velocity and acceleration, absolute (rad) for
/// positions.
pub const CHECK_TOLERANCE: f64 = 1e-9;

/// One axis's cubic between two PVT points. `Copy`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Hermite {
    p0: f64,
    v0: f64,
    p1: f64,
    v1: f64,
    dt: f64,
    c2: f64,
    c3: f64,
    /// Inputs finite, dt > 0 and coefficients finite.
    valid: bool,
}

impl Hermite {
    /// The segment from (p0, v0) to (p1, v1) over `dt` seconds. Never fails: an invalid
    /// segment (non-finite value, dt <= 0) is reported by [`Hermite::check`] and samples as
    /// holding p0 at rest. Use [`Hermite::try_new`] to get the error at once.
    pub fn new(p0: f64, v0: f64, p1: f64, v1: f64, dt: f64) -> Hermite {
        let mut h = Hermite {
            p0,
            v0,
            p1,
            v1,
            dt,
            c2: 0.0,
            c3: 0.0,
            valid: false,
        };
        if h.validate().is_ok() {
            h.c2 = (3.0 * (p1 - p0) / dt - 2.0 * v0 - v1) / dt;
            h.c3 = (2.0 * (p0 - p1) / dt + v0 + v1) / (dt * dt);
            h.valid = true;
        }
        h
    }

    /// As [`Hermite::new`], but rejects non-finite values and dt <= 0.
    pub fn try_new(p0: f64, v0: f64, p1: f64, v1: f64, dt: f64) -> Result<Hermite, SegmentError> {
        let h = Hermite::new(p0, v0, p1, v1, dt);
        h.validate().map(|()| h)
    }

    fn validate(&self) -> Result<(), SegmentError> {
        let values = [
            ("start position", self.p0),
            ("start velocity", self.v0),
            ("end position", self.p1),
            ("end velocity", self.v1),
        ];
        for (name, value) in values {
            if !value.is_finite() {
                return Err(SegmentError::NonFinite { name, value });
            }
        }
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(SegmentError::Duration { value: self.dt });
        }
        // The coefficients themselves may overflow for absurd inputs (huge p, tiny dt).
        let c2 = (3.0 * (self.p1 - self.p0) / self.dt - 2.0 * self.v0 - self.v1) / self.dt;
        let c3 = (2.0 * (self.p0 - self.p1) / self.dt + self.v0 + self.v1) / (self.dt * self.dt);
        if !(c2.is_finite() && c3.is_finite()) {
            return Err(SegmentError::NonFinite {
                name: "cubic coefficient",
                value: c3 * c2,
            });
        }
        Ok(())
    }

    /// (position, velocity, acceleration) at τ seconds into the segment, τ clamped to [0, dt]
    /// (NaN counts as 0). At τ = 0 and τ = dt position and velocity are exactly the knots'.
    pub fn sample(&self, tau: f64) -> (f64, f64, f64) {
        if !self.valid {
            return (self.p0, 0.0, 0.0);
        }
        if tau.is_nan() || tau <= 0.0 {
            return (self.p0, self.v0, 2.0 * self.c2);
        }
        if tau >= self.dt {
            return (self.p1, self.v1, self.acceleration_at(self.dt));
        }
        (
            self.position_at(tau),
            self.velocity_at(tau),
            self.acceleration_at(tau),
        )
    }

    /// Segment duration (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Jerk (rad/s³), constant over the segment: 6·c3.
    pub fn jerk(&self) -> f64 {
        6.0 * self.c3
    }

    /// Polynomial coefficients [c0, c1, c2, c3] of p(τ).
    pub fn coefficients(&self) -> [f64; 4] {
        [self.p0, self.v0, self.c2, self.c3]
    }

    fn position_at(&self, t: f64) -> f64 {
        self.p0 + t * (self.v0 + t * (self.c2 + t * self.c3))
    }

    fn velocity_at(&self, t: f64) -> f64 {
        self.v0 + t * (2.0 * self.c2 + 3.0 * self.c3 * t)
    }

    fn acceleration_at(&self, t: f64) -> f64 {
        2.0 * self.c2 + 6.0 * self.c3 * t
    }

    /// Checks the whole segment against the position range [min, max] and the velocity and
    /// acceleration limits (closed form, see the module doc). Errors name the value, where in
    /// the segment it occurs, and the limit.
    pub fn check(&self, min: f64, max: f64, limits: AxisLimits) -> Result<(), SegmentError> {
        self.validate()?;
        if !(min.is_finite() && max.is_finite() && min < max) {
            return Err(SegmentError::Range { min, max });
        }
        let ok = |x: f64| x.is_finite() && x > 0.0;
        if !ok(limits.velocity) {
            return Err(SegmentError::Limit {
                name: "velocity",
                value: limits.velocity,
            });
        }
        if !ok(limits.acceleration) {
            return Err(SegmentError::Limit {
                name: "acceleration",
                value: limits.acceleration,
            });
        }
        let dt = self.dt;
        let inside = |t: f64| t > 0.0 && t < dt;

        // Positions: both knots, then the interior extrema (roots of v).
        let (lo, hi) = (min - CHECK_TOLERANCE, max + CHECK_TOLERANCE);
        let roots = quadratic_roots(3.0 * self.c3, 2.0 * self.c2, self.v0);
        let candidates = [Some(0.0), Some(dt), roots[0], roots[1]];
        for tau in candidates.into_iter().flatten() {
            if tau == 0.0 || tau == dt || inside(tau) {
                let position = if tau == 0.0 {
                    self.p0
                } else if tau == dt {
                    self.p1
                } else {
                    self.position_at(tau)
                };
                if !(position >= lo && position <= hi) {
                    return Err(SegmentError::Position {
                        position,
                        tau,
                        min,
                        max,
                    });
                }
            }
        }

        // Velocity: both knots and the interior extremum of v.
        let v_lim = limits.velocity * (1.0 + CHECK_TOLERANCE);
        let mut v_points = [Some((0.0, self.v0)), Some((dt, self.v1)), None];
        if self.c3 != 0.0 {
            let t_star = -self.c2 / (3.0 * self.c3);
            if inside(t_star) {
                v_points[2] = Some((t_star, self.velocity_at(t_star)));
            }
        }
        for (tau, velocity) in v_points.into_iter().flatten() {
            if velocity.is_nan() || velocity.abs() > v_lim {
                return Err(SegmentError::Velocity {
                    velocity,
                    tau,
                    limit: limits.velocity,
                });
            }
        }

        // Acceleration is linear in τ: its extremes are at the knots.
        let a_lim = limits.acceleration * (1.0 + CHECK_TOLERANCE);
        for tau in [0.0, dt] {
            let acceleration = self.acceleration_at(tau);
            if acceleration.is_nan() || acceleration.abs() > a_lim {
                return Err(SegmentError::Acceleration {
                    acceleration,
                    tau,
                    limit: limits.acceleration,
                });
            }
        }
        Ok(())
    }
}

/// Real roots of a·x² + b·x + c = 0 (numerically stable form); `None` where there is none.
fn quadratic_roots(a: f64, b: f64, c: f64) -> [Option<f64>; 2] {
    let finite = |x: f64| if x.is_finite() { Some(x) } else { None };
    if a == 0.0 {
        return if b == 0.0 {
            [None, None]
        } else {
            [finite(-c / b), None]
        };
    }
    let disc = b * b - 4.0 * a * c;
    if disc.is_nan() || disc < 0.0 {
        return [None, None];
    }
    let q = -0.5 * (b + if b < 0.0 { -disc.sqrt() } else { disc.sqrt() });
    if q == 0.0 {
        return [Some(0.0), None];
    }
    [finite(q / a), finite(c / q)]
}

/// The six axes' segments between two PVT points. `Copy`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PvtSegment {
    axes: [Hermite; NUM_AXES],
}

impl PvtSegment {
    /// The segment from `from` to `to` over `dt` seconds (see [`Hermite::new`]).
    pub fn new(from: &PvtPoint, to: &PvtPoint, dt: f64) -> PvtSegment {
        PvtSegment {
            axes: std::array::from_fn(|i| {
                Hermite::new(
                    from.position[i],
                    from.velocity[i],
                    to.position[i],
                    to.velocity[i],
                    dt,
                )
            }),
        }
    }

    /// Commanded state τ seconds into the segment (τ clamped to [0, dt]).
    pub fn sample(&self, tau: f64) -> JointSample {
        let mut out = JointSample::default();
        for (i, h) in self.axes.iter().enumerate() {
            (out.position[i], out.velocity[i], out.acceleration[i]) = h.sample(tau);
        }
        out
    }

    /// Checks every axis (see [`Hermite::check`]); the error names the first failing axis.
    pub fn check(
        &self,
        min: &[f64; NUM_AXES],
        max: &[f64; NUM_AXES],
        limits: &[AxisLimits; NUM_AXES],
    ) -> Result<(), PvtSegmentError> {
        for (axis, h) in self.axes.iter().enumerate() {
            h.check(min[axis], max[axis], limits[axis])
                .map_err(|error| PvtSegmentError { axis, error })?;
        }
        Ok(())
    }

    /// One axis's segment (0-based index).
    pub fn axis(&self, axis: usize) -> Option<&Hermite> {
        self.axes.get(axis)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const LIM: AxisLimits = AxisLimits {
        velocity: 20.0,
        acceleration: 1e4,
        jerk: None,
    };

    #[test]
    fn interior_overshoot_is_caught_although_the_knots_are_inside() {
        // v(τ) = 12 − 4200τ + 3e5τ² has a root at τ = 4 ms, where p = 1.0008 > 1.
        let seg = Hermite::new(0.98, 12.0, 0.99, 0.0, 0.01);
        match seg.check(-1.0, 1.0, LIM) {
            Err(SegmentError::Position {
                position, tau, max, ..
            }) => {
                assert!((tau - 0.004).abs() < 1e-12, "{tau}");
                assert!(
                    (position - 1.0008).abs() < 1e-12 && max == 1.0,
                    "{position}"
                );
            }
            other => panic!("expected a position error, got {other:?}"),
        }
        assert_eq!(seg.check(-1.0, 1.01, LIM), Ok(()));
        let msg = seg.check(-1.0, 1.0, LIM).unwrap_err().to_string();
        assert!(msg.contains("1.0008") && msg.contains("[-1, 1]"), "{msg}");
    }

    #[test]
    fn interior_velocity_peak_and_end_accelerations_are_checked() {
        // Rest to rest over 0.1 rad in 0.1 s: v peaks at 1.5 rad/s in the middle, a(0) = 60.
        let seg = Hermite::new(0.0, 0.0, 0.1, 0.0, 0.1);
        let slow = AxisLimits {
            velocity: 1.2,
            acceleration: 100.0,
            jerk: None,
        };
        match seg.check(-1.0, 1.0, slow) {
            Err(SegmentError::Velocity {
                velocity,
                tau,
                limit,
            }) => {
                assert!(
                    (velocity - 1.5).abs() < 1e-12 && (tau - 0.05).abs() < 1e-12 && limit == 1.2
                );
            }
            other => panic!("expected a velocity error, got {other:?}"),
        }
        let weak = AxisLimits {
            velocity: 2.0,
            acceleration: 59.0,
            jerk: None,
        };
        assert!(
            matches!(seg.check(-1.0, 1.0, weak), Err(SegmentError::Acceleration { tau, .. }) if tau == 0.0)
        );
        let fine = AxisLimits {
            velocity: 1.5,
            acceleration: 60.0,
            jerk: None,
        };
        assert_eq!(seg.check(-1.0, 1.0, fine), Ok(()));
        assert!((seg.jerk() + 6.0 * 0.2 / 1e-3).abs() < 1e-9);
    }

    #[test]
    fn invalid_segments_are_typed_errors() {
        assert!(matches!(
            Hermite::try_new(0.0, 0.0, 1.0, 0.0, 0.0),
            Err(SegmentError::Duration { .. })
        ));
        assert!(matches!(
            Hermite::try_new(0.0, f64::NAN, 1.0, 0.0, 0.01),
            Err(SegmentError::NonFinite {
                name: "start velocity",
                ..
            })
        ));
        let h = Hermite::new(0.0, 0.0, 1.0, 0.0, -1.0);
        assert_eq!(h.sample(0.5), (0.0, 0.0, 0.0));
        assert!(h.check(-1.0, 1.0, LIM).is_err());
        let ok = Hermite::new(0.0, 0.0, 0.0, 0.0, 0.01);
        assert!(matches!(
            ok.check(1.0, 1.0, LIM),
            Err(SegmentError::Range { .. })
        ));
        let zero = AxisLimits {
            velocity: 0.0,
            ..LIM
        };
        assert!(matches!(
            ok.check(-1.0, 1.0, zero),
            Err(SegmentError::Limit {
                name: "velocity",
                ..
            })
        ));
    }

    #[test]
    fn six_axis_segment_names_the_failing_axis() {
        let from = PvtPoint::default();
        let mut to = PvtPoint::default();
        to.position[4] = 0.1;
        let seg = PvtSegment::new(&from, &to, 0.1);
        let slow = [AxisLimits {
            velocity: 1.2,
            acceleration: 100.0,
            jerk: None,
        }; 6];
        let err = seg.check(&[-1.0; 6], &[1.0; 6], &slow).unwrap_err();
        assert_eq!(err.axis, 4);
        assert!(err.to_string().starts_with("axis index 4"));
        assert_eq!(seg.sample(0.1).position, to.position);
    }

    fn knot() -> impl Strategy<Value = (f64, f64)> {
        (-1.2..1.2f64, -3.0..3.0f64)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(500))]

        #[test]
        fn passes_through_knots_with_continuous_velocity(
            knots in proptest::collection::vec(knot(), 2..12),
            dt in 0.002..0.05f64,
        ) {
            let segs: Vec<Hermite> = knots.windows(2)
                .map(|w| Hermite::new(w[0].0, w[0].1, w[1].0, w[1].1, dt)).collect();
            for (k, s) in segs.iter().enumerate() {
                let (p0, v0, _) = s.sample(0.0);
                let (p1, v1, _) = s.sample(dt);
                prop_assert_eq!((p0, v0), knots[k]);
                prop_assert_eq!((p1, v1), knots[k + 1]);
                // The polynomial itself (not only the clamped ends) meets the knots.
                let (pe, ve) = (s.position_at(dt), s.velocity_at(dt));
                prop_assert!((pe - p1).abs() < 1e-9 && (ve - v1).abs() < 1e-6);
                // Matches the Hermite-basis form.
                let tau = 0.37 * dt;
                let x = tau / dt;
                let basis = (2.0*x*x*x - 3.0*x*x + 1.0) * p0 + (x*x*x - 2.0*x*x + x) * dt * v0
                    + (-2.0*x*x*x + 3.0*x*x) * p1 + (x*x*x - x*x) * dt * v1;
                prop_assert!((s.sample(tau).0 - basis).abs() < 1e-12);
            }
            for w in segs.windows(2) {
                let (pa, va, _) = w[0].sample(dt);
                let (pb, vb, _) = w[1].sample(0.0);
                prop_assert_eq!((pa, va), (pb, vb));
                // Approaching the knot from inside the first segment also meets it.
                let (pi, vi, _) = w[0].sample(dt * (1.0 - 1e-9));
                prop_assert!((pi - pb).abs() < 1e-8 && (vi - vb).abs() < 1e-5);
            }
        }

        #[test]
        fn check_agrees_with_dense_sampling(
            (p0, v0) in knot(), (p1, v1) in knot(), dt in 0.005..0.2f64, a_max in 10.0..2000.0f64,
        ) {
            let (min, max) = (-1.0, 1.0);
            let lim = AxisLimits { velocity: 2.0, acceleration: a_max, jerk: None };
            let seg = Hermite::new(p0, v0, p1, v1, dt);
            let verdict = seg.check(min, max, lim);
            // Worst excess over the limits found on a dense grid, relative to each limit.
            let mut excess: f64 = 0.0;
            let n = 4000;
            for k in 0..=n {
                let (p, v, a) = seg.sample(dt * k as f64 / n as f64);
                excess = excess.max(p - max).max(min - p);
                excess = excess.max(v.abs() / lim.velocity - 1.0).max(a.abs() / lim.acceleration - 1.0);
            }
            if verdict.is_ok() {
                prop_assert!(excess <= 1e-8, "check passed but the grid exceeds a limit by {excess}");
            }
            if excess > 1e-6 {
                prop_assert!(verdict.is_err(), "grid exceeds a limit by {excess} but check passed");
            }
        }
    }
}
