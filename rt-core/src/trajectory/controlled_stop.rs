//! Controlled stops and stopping distances. Planning and sampling are O(1) per axis,
//! allocation- and panic-free: they run **inside the cycle** (a stop is planned in the cycle
//! that decides to stop).
//!
//! Each axis stops on its own, as fast as its limits allow:
//! - **second order** (no jerk limit): constant deceleration D from the current velocity until
//!   v = 0; the current acceleration is dropped at once. Distance d₂ = v²/(2D).
//! - **jerk-limited** from (v, a): Ruckig's three-phase brake: ramp a at ±J to a peak
//!   deceleration of at most D (or from beyond D back to D), hold it, ramp back to a = 0 exactly
//!   when v reaches 0. From a = 0 the distance is d₃ (below). If the axis is already braking so
//!   hard that ramping a back to zero would reverse it, the velocity crosses zero once and the
//!   axis comes back to rest (unavoidable under the jerk limit).
//!
//! After `duration()` every axis holds its end position with v = a = 0 exactly.
//!
//! The stopping distances: a stop from v at a = 0 is the time reverse of accelerating from rest
//! to |v| ([`super::profile`]'s closed form, with the deceleration D for A). It takes |v|/D
//! without a jerk limit, |v|/D + D/J when |v|·J ≥ D² (the deceleration reaches D), 2·√(|v|/J)
//! when it does not, and, the velocity falling symmetrically, covers |v| times half that time:
//! d₂ = v²/(2D) without a jerk limit; d₃ = v²/(2D) + |v|·D/(2J), or |v|^{3/2}/√J. For example
//! from 90°/s at D = 180°/s², J = 1800°/s³: d₂ = 22.5°, d₃ = 22.5° + 4.5° = 27°.
//!
//! ```
//! use mcm_rt_core::trajectory::{StopPlan, stopping_distance};
//! let deg = std::f64::consts::PI / 180.0;
//! let v = 90.0 * deg;
//! assert!((stopping_distance(v, 180.0 * deg, None) - 22.5 * deg).abs() < 1e-12);
//! assert!((stopping_distance(v, 180.0 * deg, Some(1800.0 * deg)) - 27.0 * deg).abs() < 1e-12);
//! let stop = StopPlan::plan([0.0; 6], [v; 6], [180.0 * deg; 6]);
//! assert!((stop.duration() - 0.5).abs() < 1e-12);
//! assert_eq!(stop.sample(0.5).velocity, [0.0; 6]);
//! ```

use super::profile::accel_time;
use super::{JointSample, StopError};
use mcm_shared::NUM_AXES;

/// Distance (≥ 0, rad) needed to stop from speed |v| starting at a = 0 with deceleration
/// `decel` and optional jerk limit (derived in the module doc):
/// d₂ = v²/(2D); d₃ = v²/(2D) + |v|·D/(2J) if |v|·J ≥ D², else |v|^{3/2}/√J.
/// Conservative on bad input: a non-finite v or a decel/jerk that is not finite and > 0 gives
/// `f64::INFINITY` ("cannot stop"). Latency (v·t_lat) is the caller's to add.
pub fn stopping_distance(v: f64, decel: f64, jerk: Option<f64>) -> f64 {
    let v = v.abs();
    let valid = |x: f64| x.is_finite() && x > 0.0;
    if !v.is_finite() || !valid(decel) || !jerk.is_none_or(valid) {
        return f64::INFINITY;
    }
    // |v| times half the time of the stop, the time reverse of accelerating to |v|.
    let t_stop = match jerk {
        None => v / decel,
        Some(j) => accel_time(v, decel, j),
    };
    v * t_stop / 2.0
}

/// Signed displacement (rad) of the stop from velocity `v` and acceleration `a` (see the module
/// doc); `f64::INFINITY` on bad input as for [`stopping_distance`].
pub fn stopping_distance_from(v: f64, a: f64, decel: f64, jerk: Option<f64>) -> f64 {
    match AxisStop::try_plan(0.0, v, a, decel, jerk) {
        Ok(s) => s.p_end,
        Err(_) => f64::INFINITY,
    }
}

/// The constant-jerk phases of a stop from (v, a) as `(duration, acceleration at its start,
/// jerk)`: what [`super::segments`] needs to chain a brake into a longer plan. Validated
/// like [`StopPlan::try_plan_from_state`] (axis index 0 in errors).
pub(crate) fn brake_phases(
    v: f64,
    a: f64,
    decel: f64,
    jerk: Option<f64>,
) -> Result<[(f64, f64, f64); 3], StopError> {
    let s = AxisStop::try_plan(0.0, v, a, decel, jerk)?;
    Ok([
        (s.t1, s.a, s.j1),
        (s.t2, s.a_peak, 0.0),
        (s.t3, s.a_peak, s.j3),
    ])
}

/// One axis's stop: up to three constant-jerk phases (jerk j1, 0, j3), then rest.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct AxisStop {
    p: f64,
    v: f64,
    a: f64,
    t1: f64,
    j1: f64,
    t2: f64,
    a_peak: f64,
    t3: f64,
    j3: f64,
    /// State at the ends of phases 1 and 2.
    p1: f64,
    v1: f64,
    p2: f64,
    v2: f64,
    p_end: f64,
    duration: f64,
}

impl AxisStop {
    /// An axis that is already held: stays at `p`.
    fn hold(p: f64) -> AxisStop {
        AxisStop {
            p,
            p1: p,
            p2: p,
            p_end: p,
            ..AxisStop::default()
        }
    }

    fn try_plan(
        p: f64,
        v: f64,
        a: f64,
        decel: f64,
        jerk: Option<f64>,
    ) -> Result<AxisStop, StopError> {
        let state = [("position", p), ("velocity", v), ("acceleration", a)];
        for (name, value) in state {
            if !value.is_finite() {
                return Err(StopError::State {
                    axis: 0,
                    name,
                    value,
                });
            }
        }
        if !(decel.is_finite() && decel > 0.0) {
            return Err(StopError::Deceleration {
                axis: 0,
                value: decel,
            });
        }
        match jerk {
            Some(j) if !(j.is_finite() && j > 0.0) => Err(StopError::Jerk { axis: 0, value: j }),
            Some(j) => Ok(AxisStop::jerk_limited(p, v, a, decel, j)),
            None => Ok(AxisStop::second_order(p, v, decel)),
        }
    }

    fn second_order(p: f64, v: f64, decel: f64) -> AxisStop {
        let sign = if v < 0.0 { -1.0 } else { 1.0 };
        AxisStop {
            p,
            v,
            t2: v.abs() / decel,
            a_peak: -sign * decel,
            ..AxisStop::default()
        }
        .finish()
    }

    fn jerk_limited(p: f64, v: f64, a: f64, decel: f64, j: f64) -> AxisStop {
        // Normalise so that the axis must end up decelerating (negative peak acceleration):
        // σ is the sign of the velocity left after ramping a straight to zero.
        let v_after = v + a * a.abs() / (2.0 * j);
        let sigma = if v_after > 0.0 || (v_after == 0.0 && a <= 0.0) {
            1.0
        } else {
            -1.0
        };
        let (vn, an) = (sigma * v, sigma * a);
        let rest = (vn + an * an.abs() / (2.0 * j)).max(0.0);
        let (a_p, t2) = if an < -decel {
            // Braking harder than allowed: ramp up to −D, hold, ramp to zero.
            (decel, rest / decel)
        } else {
            let triangle = (j * vn + an * an / 2.0).max(0.0).sqrt();
            if triangle <= decel {
                (triangle, 0.0)
            } else {
                (
                    decel,
                    ((vn + an * an / (2.0 * j) - decel * decel / j) / decel).max(0.0),
                )
            }
        };
        let j1 = if an + a_p >= 0.0 { -j } else { j };
        let stop = AxisStop {
            p,
            v,
            a,
            t1: (an + a_p).abs() / j,
            j1: sigma * j1,
            t2,
            a_peak: -sigma * a_p,
            t3: a_p / j,
            j3: sigma * j,
            ..AxisStop::default()
        };
        stop.finish()
    }

    /// Fills in the phase-boundary states and the end.
    fn finish(mut self) -> AxisStop {
        let (t1, t2, t3) = (self.t1, self.t2, self.t3);
        self.p1 = self.p + self.v * t1 + self.a * t1 * t1 / 2.0 + self.j1 * t1 * t1 * t1 / 6.0;
        self.v1 = self.v + self.a * t1 + self.j1 * t1 * t1 / 2.0;
        self.p2 = self.p1 + self.v1 * t2 + self.a_peak * t2 * t2 / 2.0;
        self.v2 = self.v1 + self.a_peak * t2;
        self.p_end =
            self.p2 + self.v2 * t3 + self.a_peak * t3 * t3 / 2.0 + self.j3 * t3 * t3 * t3 / 6.0;
        self.duration = t1 + t2 + t3;
        self
    }

    fn sample(&self, t: f64) -> (f64, f64, f64) {
        if t.is_nan() || t >= self.duration {
            return if t.is_nan() && self.duration > 0.0 {
                (self.p, self.v, self.a)
            } else {
                (self.p_end, 0.0, 0.0)
            };
        }
        let t = t.max(0.0);
        if t < self.t1 {
            let (a, j) = (self.a, self.j1);
            (
                self.p + t * (self.v + t * (a / 2.0 + t * j / 6.0)),
                self.v + t * (a + t * j / 2.0),
                a + j * t,
            )
        } else if t < self.t1 + self.t2 {
            let tau = t - self.t1;
            let a = self.a_peak;
            (
                self.p1 + tau * (self.v1 + tau * a / 2.0),
                self.v1 + a * tau,
                a,
            )
        } else {
            let tau = (t - self.t1 - self.t2).min(self.t3);
            let (a, j) = (self.a_peak, self.j3);
            (
                self.p2 + tau * (self.v2 + tau * (a / 2.0 + tau * j / 6.0)),
                self.v2 + tau * (a + tau * j / 2.0),
                a + j * tau,
            )
        }
    }
}

/// A stop of all six axes, each as fast as its own limits allow. `Copy`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StopPlan {
    axes: [AxisStop; NUM_AXES],
    duration: f64,
}

impl StopPlan {
    /// Second-order stop from positions `p` and velocities `v` at decelerations `decel`
    /// (per axis, rad/s²). Never fails; see [`StopPlan::plan_from_state`] for bad input.
    pub fn plan(p: [f64; NUM_AXES], v: [f64; NUM_AXES], decel: [f64; NUM_AXES]) -> StopPlan {
        StopPlan::plan_from_state(p, v, [0.0; NUM_AXES], decel, [None; NUM_AXES])
    }

    /// Stop from the state (p, v, a) with per-axis deceleration and optional jerk limit.
    /// Never fails, because a stop must always be possible: an axis with a non-finite velocity
    /// or acceleration, or a deceleration that is not finite and > 0, is stopped at once
    /// (holds `p`); an invalid jerk limit is ignored (second-order stop). Use
    /// [`StopPlan::try_plan_from_state`] to have such input reported instead.
    pub fn plan_from_state(
        p: [f64; NUM_AXES],
        v: [f64; NUM_AXES],
        a: [f64; NUM_AXES],
        decel: [f64; NUM_AXES],
        jerk: [Option<f64>; NUM_AXES],
    ) -> StopPlan {
        let axes = std::array::from_fn(|i| {
            let jerk_i = jerk[i].filter(|j| j.is_finite() && *j > 0.0);
            AxisStop::try_plan(p[i], v[i], a[i], decel[i], jerk_i).unwrap_or(AxisStop::hold(p[i]))
        });
        StopPlan::from_axes(axes)
    }

    /// As [`StopPlan::plan_from_state`], but any non-finite state value or invalid
    /// deceleration or jerk is an error naming the axis.
    pub fn try_plan_from_state(
        p: [f64; NUM_AXES],
        v: [f64; NUM_AXES],
        a: [f64; NUM_AXES],
        decel: [f64; NUM_AXES],
        jerk: [Option<f64>; NUM_AXES],
    ) -> Result<StopPlan, StopError> {
        let mut axes = [AxisStop::default(); NUM_AXES];
        for (i, axis) in axes.iter_mut().enumerate() {
            *axis = AxisStop::try_plan(p[i], v[i], a[i], decel[i], jerk[i])
                .map_err(|e| with_axis(e, i))?;
        }
        Ok(StopPlan::from_axes(axes))
    }

    fn from_axes(axes: [AxisStop; NUM_AXES]) -> StopPlan {
        let duration = axes.iter().fold(0.0, |d: f64, a| d.max(a.duration));
        StopPlan { axes, duration }
    }

    /// Time until the last axis is at rest (s).
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// Each axis's own stopping time (s).
    pub fn durations(&self) -> [f64; NUM_AXES] {
        self.axes.map(|a| a.duration)
    }

    /// Where each axis comes to rest (rad).
    pub fn end_positions(&self) -> [f64; NUM_AXES] {
        self.axes.map(|a| a.p_end)
    }

    /// Signed stopping distance per axis (rad).
    pub fn distances(&self) -> [f64; NUM_AXES] {
        self.axes.map(|a| a.p_end - a.p)
    }

    /// Commanded state `t` seconds after the stop began (t clamped to >= 0; NaN counts as 0).
    /// From an axis's own duration on it holds its end position with v = a = 0 exactly.
    pub fn sample(&self, t: f64) -> JointSample {
        let mut out = JointSample::default();
        for (i, axis) in self.axes.iter().enumerate() {
            (out.position[i], out.velocity[i], out.acceleration[i]) = axis.sample(t);
        }
        out
    }
}

fn with_axis(e: StopError, axis: usize) -> StopError {
    match e {
        StopError::State { name, value, .. } => StopError::State { axis, name, value },
        StopError::Deceleration { value, .. } => StopError::Deceleration { axis, value },
        StopError::Jerk { value, .. } => StopError::Jerk { axis, value },
    }
}

#[cfg(test)]
mod tests;
