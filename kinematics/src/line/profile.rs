//! The time law of the path parameter: s goes from 0 to 1 at rest at both ends, its
//! velocity, acceleration and jerk within V, A and J. With a jerk limit a double-S (jerk ±J
//! ramps, an acceleration plateau at A when it is reached, a cruise at V when it is reached,
//! mirrored for the deceleration); without one a trapezoid (or a triangle). Time-optimal for
//! those bounds; closed form, O(1), no allocation.
//!
//! Going from rest to a velocity v takes T(v) = v/A + A/J when v·J ≥ A² (the acceleration
//! reaches A), else 2√(v/J) (it peaks at √(v·J)); without a jerk limit v/A. The acceleration
//! half covers v·T(v)/2, so the profile cruises at V when V·T(V) ≤ 1, else it peaks at the v
//! with v·T(v) = 1. (`mcm-rt-core`'s joint-move profile, `trajectory::profile`, is the same
//! law over any distance.)

/// A rest-to-rest profile of s from 0 to 1. Plain data.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct PathProfile {
    /// Jerk of the ramps (0: a trapezoid).
    jerk: f64,
    /// Duration of each jerk ramp.
    t_j: f64,
    /// Duration of the acceleration half.
    t_acc: f64,
    /// Duration of the cruise.
    t_v: f64,
    /// Peak velocity and acceleration.
    v: f64,
    a: f64,
    /// s at the end of the acceleration half.
    s_acc: f64,
    duration: f64,
}

impl PathProfile {
    /// The profile under the bounds `v_max`, `a_max` (> 0, finite) and the jerk bound
    /// (`None`: a trapezoid). Bounds that are not positive give the zero profile (duration 0).
    pub fn new(v_max: f64, a_max: f64, jerk: Option<f64>) -> PathProfile {
        let ok = |x: f64| x.is_finite() && x > 0.0;
        if !(ok(v_max) && ok(a_max) && jerk.is_none_or(ok)) {
            return PathProfile::default();
        }
        let (v, a, j) = match jerk {
            None => (v_max.min(a_max.sqrt()), a_max, 0.0),
            Some(j) => {
                let rise = |v: f64| {
                    if v * j >= a_max * a_max {
                        v / a_max + a_max / j
                    } else {
                        2.0 * (v / j).sqrt()
                    }
                };
                let v = if v_max * rise(v_max) <= 1.0 {
                    v_max
                } else {
                    // v²/A + v·A/J = 1, its root written without cancellation ...
                    let r = a_max / j;
                    let v = 2.0 / (r + (r * r + 4.0 / a_max).sqrt());
                    if v * j >= a_max * a_max {
                        v
                    } else {
                        // ... or, without an acceleration plateau, 2·v^(3/2)/√J = 1.
                        (j.sqrt() / 2.0).cbrt().powi(2)
                    }
                };
                let v = v.min(v_max);
                (v, a_max.min((v * j).sqrt()), j)
            }
        };
        let t_j = if j > 0.0 { a / j } else { 0.0 };
        let t_acc = 2.0 * t_j + (v / a - t_j).max(0.0);
        let s_acc = v * t_acc / 2.0;
        let t_v = (1.0 / v - t_acc).max(0.0);
        PathProfile {
            jerk: j,
            t_j,
            t_acc,
            t_v,
            v,
            a,
            s_acc,
            duration: 2.0 * t_acc + t_v,
        }
    }

    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// (s, ds/dt, d²s/dt²) at time `t` [s]: (0, 0, 0) before the start (and for NaN),
    /// exactly (1, 0, 0) from the end on.
    pub fn sample(&self, t: f64) -> (f64, f64, f64) {
        if t.is_nan() || t <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        if t >= self.duration {
            return (1.0, 0.0, 0.0);
        }
        let (s, v, a) = if t <= self.t_acc {
            self.rising(t)
        } else if t <= self.t_acc + self.t_v {
            (self.s_acc + self.v * (t - self.t_acc), self.v, 0.0)
        } else {
            let (s, v, a) = self.rising(self.duration - t);
            (1.0 - s, v, -a)
        };
        (s.clamp(0.0, 1.0), v, a)
    }

    /// The acceleration half, 0 ≤ t ≤ t_acc.
    fn rising(&self, t: f64) -> (f64, f64, f64) {
        let (j, a, tj) = (self.jerk, self.a, self.t_j);
        if t < tj {
            (j * t * t * t / 6.0, j * t * t / 2.0, j * t)
        } else if t <= self.t_acc - tj {
            let tau = t - tj;
            let (s1, v1) = (a * tj * tj / 6.0, a * tj / 2.0);
            (s1 + v1 * tau + a * tau * tau / 2.0, v1 + a * tau, a)
        } else {
            // The last ramp, from its end backwards (exact peak velocity there).
            let tau = (self.t_acc - t).clamp(0.0, tj);
            (
                self.s_acc - self.v * tau + j * tau * tau * tau / 6.0,
                self.v - j * tau * tau / 2.0,
                j * tau,
            )
        }
    }
}
