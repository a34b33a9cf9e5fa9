//! The dynamic limit check (`docs/safety.md`, "Braking distance"): stop an axis that could no
//! longer stop before its limit ([`BrakingDistance`], the third per-cycle check: in the modes
//! with a motion other than a planned one, except while a planned move or stop runs, which was
//! validated when planned), and the preventive velocity cap that keeps the check from firing.
//! A torque command is judged with the acceleration it produces before it is sent
//! ([`check_braking_accelerating`], `controller/motion.rs`).
//!
//! Runs inside the cycle (pure, allocation-free, panic-free).
//!
//! Parameters ([`SafetyParams`]): `q_min`, `q_max`, `margin` (`safety.limit_margin_deg`),
//! `reaction_s` (`safety.reaction_cycles`), `brake_decel` (`safety.braking_efficiency` x
//! `axis.max_acceleration_deg_s2`), `stop_jerk`; their bounds are
//! `mcm_shared::config::LIMIT_MARGIN_MAX_DEG`, `REACTION_MAX_S`, `BRAKING_EFFICIENCY_MIN` and
//! `ACCELERATION_MAX_DEG_S2`.
//!
//! For an axis moving toward `q_max` at `v > 0` (mirrored for `q_min`):
//! ```text
//! stop = q + v*Ts + v*t_lat + v^2 / (2 a_b)        trips if  stop > q_max - margin
//! ```
//! with `Ts` the cycle (one-cycle look-ahead: the next sample is already covered),
//! `t_lat = reaction_cycles * Ts` (plus `a_b / 2j` for a jerk-limited stop), and
//! `a_b = braking_efficiency * max_acceleration`. Only the direction of motion is checked:
//! moving away from a limit never trips here (the position check covers being beyond it).
//! If the check passed at the previous sample, the axis stops (after the latency, braking at
//! `a_b`) at or before `q_max - margin`; the property tests simulate exactly that.
//!
//! The stop the controller executes on a trip must brake at least at `a_b` after at most
//! `t_lat`; if it ramps the deceleration with a jerk limit, build the parameters with
//! [`SafetyParams::with_jerk_limited_stop`].
//!
//! ```
//! use mcm_rt_core::safety::braking_distance;
//! // 90 deg/s at 180 deg/s^2, no latency: 22.5 deg (any consistent unit works).
//! assert!((braking_distance(90.0, 180.0, 0.0) - 22.5).abs() < 1e-12);
//! ```

use super::{Check, CycleCheck, CycleInputs, SafetyParams, Situation, Violation};
use mcm_shared::NUM_AXES;

/// The braking-distance check on the measured state ([`check_braking`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BrakingDistance;

impl CycleCheck for BrakingDistance {
    const ID: Check = Check::BrakingDistance;

    fn runs(&self, now: &Situation) -> bool {
        now.free_motion_mode() && !now.planned_motion
    }

    fn verdict(
        &mut self,
        params: &SafetyParams,
        inputs: &CycleInputs<'_>,
    ) -> Result<(), Violation> {
        check_braking(params, inputs.position, inputs.velocity)
    }
}

/// Slack kept by [`velocity_cap`] below the margin line [rad], so that moving exactly at the
/// cap never trips [`check_braking`] through rounding. (1e-9 rad = 6e-8 deg.)
pub const CAP_SLACK_RAD: f64 = 1e-9;

/// Distance travelled from speed `|v|` until standstill: `|v| * latency_s` at constant speed,
/// then `v^2 / (2 decel)` at constant deceleration. A deceleration that is not > 0 gives
/// `INFINITY`; a NaN input gives NaN (callers treat both as a trip).
pub fn braking_distance(v: f64, decel: f64, latency_s: f64) -> f64 {
    if decel.is_nan() || decel <= 0.0 {
        return f64::INFINITY;
    }
    let v = v.abs();
    // Negative latency is meaningless: count it as zero (NaN stays NaN).
    let lat = if latency_s < 0.0 { 0.0 } else { latency_s };
    v * lat + v * v / (2.0 * decel)
}

/// Where axis `axis` at `q` moving at `v` would stand still if the check tripped now:
/// `q + v*Ts ± braking_distance` in the direction of motion [rad]. NaN for a bad axis index.
pub fn predicted_stop(params: &SafetyParams, axis: usize, q: f64, v: f64) -> f64 {
    if axis >= NUM_AXES {
        return f64::NAN;
    }
    let d = braking_distance(v, params.brake_decel[axis], params.braking_latency_s(axis));
    let d = if v < 0.0 {
        -d
    } else if v > 0.0 {
        d
    } else {
        0.0
    };
    q + v * params.cycle_s + d
}

/// `Err` for the first axis whose predicted stop position passes its limit minus the margin
/// in the direction of motion (`value` = predicted stop, `limit` = `q_max - margin` or
/// `q_min + margin`). A non-finite position or velocity trips.
pub fn check_braking(
    params: &SafetyParams,
    q: &[f64; NUM_AXES],
    qd: &[f64; NUM_AXES],
) -> Result<(), Violation> {
    for (i, (&x, &v)) in q.iter().zip(qd).enumerate() {
        let hi = params.q_max[i] - params.margin;
        let lo = params.q_min[i] + params.margin;
        let stop = predicted_stop(params, i, x, v);
        let (tripped, limit) = if !(x.is_finite() && v.is_finite()) {
            (true, if v < 0.0 { lo } else { hi })
        } else if v > 0.0 {
            (stop.is_nan() || stop > hi, hi)
        } else if v < 0.0 {
            (stop.is_nan() || stop < lo, lo)
        } else {
            (false, hi)
        };
        if tripped {
            return Err(Violation {
                check: Check::BrakingDistance,
                axis: i,
                value: stop,
                limit,
            });
        }
    }
    Ok(())
}

/// [`check_braking`] for axes driven by torques (TORQUE_CONTROL): each axis goes on
/// accelerating at `qdd` (the acceleration the commanded torques produce, from the arm's
/// model) until the stop begins, `Ts + t_lat` later, and then brakes at `a_b`:
/// ```text
/// t = Ts + t_lat,  a+ = max(qdd, 0),  v1 = v + a+ t,  x1 = q + v t + a+ t^2 / 2
/// trips if  v1 > 0  and  x1 + v1^2 / (2 a_b) > q_max - margin        (mirrored for q_min)
/// ```
/// With `qdd` 0 it is [`check_braking`]. Without it, a torque from rest next to a limit
/// reaches the limit before the measurement shows the motion (the P-Rob2's flange: 1.4 deg
/// and 250 deg/s in four cycles). Non-finite input trips, as in [`check_braking`].
pub fn check_braking_accelerating(
    params: &SafetyParams,
    q: &[f64; NUM_AXES],
    qd: &[f64; NUM_AXES],
    qdd: &[f64; NUM_AXES],
) -> Result<(), Violation> {
    for i in 0..NUM_AXES {
        let (x, v, a) = (q[i], qd[i], qdd[i]);
        let hi = params.q_max[i] - params.margin;
        let lo = params.q_min[i] + params.margin;
        let t = params.cycle_s + params.braking_latency_s(i);
        let decel = params.brake_decel[i];
        let violation = |value: f64, limit: f64| Violation {
            check: Check::BrakingDistance,
            axis: i,
            value,
            limit,
        };
        if !(x.is_finite() && v.is_finite() && a.is_finite()) {
            return Err(violation(f64::NAN, if v < 0.0 { lo } else { hi }));
        }
        let up = a.max(0.0);
        let (v1, x1) = (v + up * t, x + v * t + 0.5 * up * t * t);
        if v1 > 0.0 {
            let stop = x1 + braking_distance(v1, decel, 0.0);
            if stop.is_nan() || stop > hi {
                return Err(violation(stop, hi));
            }
        }
        let down = a.min(0.0);
        let (v1, x1) = (v + down * t, x + v * t + 0.5 * down * t * t);
        if v1 < 0.0 {
            let stop = x1 - braking_distance(v1, decel, 0.0);
            if stop.is_nan() || stop < lo {
                return Err(violation(stop, lo));
            }
        }
    }
    Ok(())
}

/// The largest speed [rad/s] (>= 0) axis `axis` at `q` may have when moving in `direction`
/// (> 0 toward `q_max`, < 0 toward `q_min`, 0: the smaller of both) without tripping
/// [`check_braking`], and never above `v_max`:
/// the solution of `v*(Ts + t_lat) + v^2/(2 a_b) = limit - margin - q - CAP_SLACK_RAD`.
/// Unlike the 5.6 formula it includes the one-cycle look-ahead, so that moving at the cap is
/// consistent with the check. 0 inside the margin band, for a bad axis, or non-finite input.
pub fn velocity_cap(params: &SafetyParams, axis: usize, q: f64, direction: f64) -> f64 {
    if axis >= NUM_AXES || !q.is_finite() || direction.is_nan() {
        return 0.0;
    }
    let up = || cap_for_distance(params, axis, params.q_max[axis] - params.margin - q);
    let down = || cap_for_distance(params, axis, q - params.q_min[axis] - params.margin);
    let cap = if direction > 0.0 {
        up()
    } else if direction < 0.0 {
        down()
    } else {
        up().min(down())
    };
    cap.min(params.v_max[axis])
}

/// Solve `v*t + v^2/(2a) = D - slack` for v >= 0, in the cancellation-free form
/// `v = 2aD' / (a t + sqrt((a t)^2 + 2aD'))`.
fn cap_for_distance(params: &SafetyParams, axis: usize, distance: f64) -> f64 {
    let d = distance - CAP_SLACK_RAD;
    let a = params.brake_decel[axis];
    let t = params.cycle_s + params.braking_latency_s(axis);
    if !(d > 0.0 && a > 0.0 && t.is_finite()) {
        return 0.0;
    }
    let at = a * t;
    let v = 2.0 * a * d / (at + (at * at + 2.0 * a * d).sqrt());
    if v.is_finite() { v } else { 0.0 }
}

#[cfg(test)]
mod tests;
