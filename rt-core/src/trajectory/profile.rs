//! 1-D rest-to-rest motion profiles. Planning and sampling both run **inside the cycle** if
//! needed: O(1), no allocation, no panics.
//!
//! - No jerk limit: **trapezoid** (accelerate at A, cruise at V, decelerate at A), or a triangle
//!   when V is not reached (peak velocity √(D·A)).
//! - Jerk limit J: **double-S** with 7 phases (jerk +J, hold a, jerk −J, cruise, mirrored),
//!   symmetric acceleration and deceleration; the acceleration or the velocity plateau may
//!   vanish when A or V is not reached.
//!
//! The plan is closed-form and time-optimal for a symmetric rest-to-rest move. Samples are
//! displacements from the start: 0 at t = 0 and exactly `distance` (with v = a = 0) from
//! `duration()` on. The deceleration half is evaluated as the mirror image of the
//! acceleration half, anchored at the end, so the end state is exact.
//!
//! ## The closed form
//!
//! Going from rest to a velocity v (and back to a = 0) takes T_acc(v):
//! - without a jerk limit, v/A;
//! - with the jerk limit J, when v·J ≥ A² (the acceleration reaches A and holds it between two
//!   ramps of A/J), v/A + A/J;
//! - when v·J < A² (the acceleration peaks at √(v·J) < A), 2·√(v/J).
//!
//! The acceleration rises and falls in equal ramps, so the velocity is symmetric about v/2 and
//! the acceleration half covers v·T_acc/2; a move peaking at v with a cruise of T_v covers
//! D = v·T_acc(v) + v·T_v and lasts 2·T_acc + T_v. The plan peaks at V when
//! D ≥ V·T_acc(V) (cruise T_v = D/V − T_acc(V)), else at the v that solves D = v·T_acc(v):
//! - without a jerk limit, v = √(D·A) (the triangle);
//! - with an acceleration plateau, v²/A + v·A/J = D, whose root, written without cancellation,
//!   is v = 2D / (A/J + √((A/J)² + 4D/A));
//! - without one, 2·v^{3/2}/√J = D, i.e. v = (D·√J/2)^{2/3}.
//!
//! For example D = 90°, V = 90°/s, A = 180°/s², J = 1800°/s³: T_acc(V) = 0.5 + 0.1 s,
//! V·T_acc(V) = 54° < 90°, so it cruises 1 − 0.6 = 0.4 s and lasts 1.6 s (the trapezoid, with
//! T_acc = 0.5 s, lasts 1.5 s).
//!
//! ```
//! use mcm_rt_core::trajectory::{AxisLimits, Profile1D};
//! let deg = std::f64::consts::PI / 180.0;
//! let lim = AxisLimits {
//!     velocity: 90.0 * deg,
//!     acceleration: 180.0 * deg,
//!     jerk: Some(1800.0 * deg),
//! };
//! let p = Profile1D::plan(90.0 * deg, lim).unwrap();
//! assert!((p.duration() - 1.6).abs() < 1e-12);
//! assert_eq!(p.sample(p.duration()), (90.0 * deg, 0.0, 0.0));
//! ```

use super::{AxisLimits, PlanError};

/// A planned rest-to-rest move over a signed distance. `Copy`, 12 numbers.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Profile1D {
    /// Signed distance (rad).
    distance: f64,
    /// |distance|.
    length: f64,
    /// +1 or −1.
    sign: f64,
    /// Jerk of the ramps (0 for a trapezoid).
    jerk: f64,
    /// Duration of each jerk ramp (0 for a trapezoid).
    t_j: f64,
    /// Duration of constant acceleration.
    t_ca: f64,
    /// Duration of the whole acceleration half: 2·t_j + t_ca.
    t_acc: f64,
    /// Duration of cruise at peak velocity.
    t_v: f64,
    duration: f64,
    a_peak: f64,
    v_peak: f64,
    /// Distance covered while accelerating: v_peak·t_acc/2.
    p_acc: f64,
}

impl Profile1D {
    /// Plans the time-optimal rest-to-rest move over `distance` (signed) under `limits`
    /// (already scaled by any velocity factor). A zero distance gives a zero-length profile.
    pub fn plan(distance: f64, limits: AxisLimits) -> Result<Profile1D, PlanError> {
        if !distance.is_finite() {
            return Err(PlanError::Distance { value: distance });
        }
        limits.validate()?;
        let length = distance.abs();
        let sign = if distance < 0.0 { -1.0 } else { 1.0 };
        let (v_max, a_max) = (limits.velocity, limits.acceleration);
        let (v_peak, a_peak, jerk) = match limits.jerk {
            None => {
                let v = if length >= v_max * v_max / a_max {
                    v_max
                } else {
                    (length * a_max).sqrt()
                };
                (v.min(v_max), a_max, 0.0)
            }
            Some(j) => {
                let v = if length >= v_max * accel_time(v_max, a_max, j) {
                    v_max
                } else {
                    // v·T_acc(v) = D with an acceleration plateau (rationalised, no cancellation):
                    let r = a_max / j;
                    let v = 2.0 * length / (r + (r * r + 4.0 * length / a_max).sqrt());
                    if v * j >= a_max * a_max {
                        v
                    } else {
                        // ... or without one: v·2√(v/J) = D.
                        let c = (length * j.sqrt() / 2.0).cbrt();
                        c * c
                    }
                };
                let v = v.min(v_max);
                let a = if v * j >= a_max * a_max {
                    a_max
                } else {
                    (v * j).sqrt().min(a_max)
                };
                (v, a, j)
            }
        };
        if length == 0.0 || !(v_peak > 0.0 && a_peak > 0.0) {
            // Zero distance, or one so small that v_peak underflows: nothing to move.
            return Ok(Profile1D {
                distance,
                sign,
                length,
                ..Profile1D::default()
            });
        }
        let t_j = if jerk > 0.0 { a_peak / jerk } else { 0.0 };
        let t_ca = (v_peak / a_peak - t_j).max(0.0);
        let t_acc = 2.0 * t_j + t_ca;
        let p_acc = v_peak * t_acc / 2.0;
        let t_v = (length / v_peak - t_acc).max(0.0);
        let duration = 2.0 * t_acc + t_v;
        if !duration.is_finite() {
            return Err(PlanError::Duration { value: duration });
        }
        let profile = Profile1D {
            distance,
            length,
            sign,
            jerk,
            t_j,
            t_ca,
            t_acc,
            t_v,
            duration,
            a_peak,
            v_peak,
            p_acc,
        };
        // Guard against limit ratios so extreme that floating point cannot plan them.
        let covered = 2.0 * p_acc + v_peak * t_v;
        let error = (covered - length).abs();
        if error.is_nan() || error > 1e-9 * length {
            return Err(PlanError::Numeric { distance });
        }
        Ok(profile)
    }

    /// Total duration (s).
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// Signed distance of the move (rad).
    pub fn distance(&self) -> f64 {
        self.distance
    }

    /// Peak |velocity| reached (rad/s).
    pub fn peak_velocity(&self) -> f64 {
        self.v_peak
    }

    /// Peak |acceleration| reached (rad/s²).
    pub fn peak_acceleration(&self) -> f64 {
        self.a_peak
    }

    /// Jerk of the ramps (`None` for a trapezoid).
    pub fn jerk(&self) -> Option<f64> {
        (self.jerk > 0.0).then_some(self.jerk)
    }

    /// True for a double-S (jerk-limited) profile, false for a trapezoid.
    pub fn is_jerk_limited(&self) -> bool {
        self.jerk > 0.0
    }

    /// Start times of the 7 phases plus the end time; phases of zero length repeat a time.
    /// (Trapezoid: the jerk phases have zero length.)
    pub fn phase_times(&self) -> [f64; 8] {
        let (tj, tca, ta) = (self.t_j, self.t_ca, self.t_acc);
        let td = ta + self.t_v;
        [
            0.0,
            tj,
            tj + tca,
            ta,
            td,
            td + tj,
            td + tj + tca,
            self.duration,
        ]
    }

    /// (displacement, velocity, acceleration) at time `t` since the start. `t` is clamped to
    /// [0, duration]; NaN counts as 0. From `duration()` on the result is exactly
    /// (distance, 0, 0).
    pub fn sample(&self, t: f64) -> (f64, f64, f64) {
        if t.is_nan() || t <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        if t >= self.duration {
            return (self.distance, 0.0, 0.0);
        }
        let cruise_end = self.t_acc + self.t_v;
        let (p, v, a) = if t <= self.t_acc {
            self.accelerating(t)
        } else if t <= cruise_end {
            (
                self.p_acc + self.v_peak * (t - self.t_acc),
                self.v_peak,
                0.0,
            )
        } else {
            let (p, v, a) = self.accelerating(self.duration - t);
            (self.length - p, v, -a)
        };
        let p = p.max(0.0).min(self.length);
        (self.sign * p, self.sign * v, self.sign * a)
    }

    /// The acceleration half (magnitudes), 0 <= t <= t_acc.
    fn accelerating(&self, t: f64) -> (f64, f64, f64) {
        let (j, a, tj) = (self.jerk, self.a_peak, self.t_j);
        if t < tj {
            (j * t * t * t / 6.0, j * t * t / 2.0, j * t)
        } else if t < tj + self.t_ca {
            let tau = t - tj;
            let (p1, v1) = (a * tj * tj / 6.0, a * tj / 2.0);
            (p1 + v1 * tau + a * tau * tau / 2.0, v1 + a * tau, a)
        } else {
            // Last jerk ramp, evaluated backwards from the end of the half (exact v_peak there).
            // Clamped to the ramp: t_acc carries the rounding of t_ca, which may exceed a tiny
            // t_j, and J·τ must not exceed the peak acceleration.
            let tau = (self.t_acc - t).max(0.0).min(tj);
            let v = self.v_peak;
            (
                self.p_acc - v * tau + j * tau * tau * tau / 6.0,
                v - j * tau * tau / 2.0,
                j * tau,
            )
        }
    }
}

/// Time to accelerate from rest to `v` (and back to a = 0) under A and J: T_acc of the module
/// doc (a stop from `v` at a = 0 is its time reverse, [`super::controlled_stop`]).
pub(super) fn accel_time(v: f64, a: f64, j: f64) -> f64 {
    if v * j >= a * a {
        v / a + a / j
    } else {
        2.0 * (v / j).sqrt()
    }
}

#[cfg(test)]
mod tests;
