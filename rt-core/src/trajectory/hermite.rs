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
mod tests;
