//! The velocity ramp of VELOCITY_CONTROL, one axis at a time: a pure function of the axis's
//! commanded state, its target velocity and its limits.
//!
//! Runs inside the cycle (pure, allocation-free, panic-free).
//!
//! Each cycle [`step`]:
//! 1. clamps the target to the axis's maximum velocity and to the braking envelope: the
//!    largest speed towards a limit from which the axis still comes to rest before it,
//!    `v * lookahead_s + v^2 / (2 brake) <= distance` ([`envelope`]), with `brake` below the
//!    deceleration the safety check's braking-distance assumes, so that a joint driven towards
//!    its limit brakes in time instead of tripping that check;
//! 2. chooses the acceleration that approaches the (clamped) target fastest while it can still
//!    be ramped down to 0 at the jerk limit without overshooting (`a dt + a^2 / (2 j) = |dv|`),
//!    within the acceleration limit and at most `j dt` away from the last one;
//! 3. integrates: `v += a dt`, `q += (v_old + v) / 2 dt`.
//!
//! The unit and property tests (`tests.rs` next to this file) simulate it: it never exceeds the
//! velocity, acceleration and jerk limits, it reaches the target, and a joint driven into a
//! limit comes to rest before it with the braking-distance check passing every cycle.

/// The limits of one axis in velocity control (SI units: rad, rad/s, rad/s^2, rad/s^3, s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RampLimits {
    /// Largest speed.
    pub velocity: f64,
    /// Largest acceleration (and deceleration).
    pub acceleration: f64,
    /// Largest jerk; `INFINITY`: none.
    pub jerk: f64,
    /// The deceleration planned for braking before a limit (at most `acceleration`).
    pub brake: f64,
    /// Time counted at full speed before the braking starts (the jerk ramp, latencies).
    pub lookahead_s: f64,
    /// Where the axis may come to rest, lowest and highest.
    pub stop_min: f64,
    pub stop_max: f64,
}

/// The commanded state of one axis.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisRamp {
    pub position: f64,
    pub velocity: f64,
    pub acceleration: f64,
}

/// The largest speed (>= 0) from which an axis `distance` before its stop point still comes to
/// rest at it: the solution of `v * lookahead_s + v^2 / (2 brake) = distance`. 0 when the
/// distance is not positive or an input is not usable.
pub fn envelope(distance: f64, brake: f64, lookahead_s: f64) -> f64 {
    if !(distance > 0.0 && brake > 0.0 && lookahead_s >= 0.0 && lookahead_s.is_finite()) {
        return 0.0;
    }
    // Cancellation-free form of the positive root.
    let at = brake * lookahead_s;
    let v = 2.0 * brake * distance / (at + (at * at + 2.0 * brake * distance).sqrt());
    if v.is_finite() { v } else { 0.0 }
}

/// The target `target` after the velocity limit and the braking envelopes at `position`.
pub fn allowed_target(position: f64, target: f64, l: &RampLimits) -> f64 {
    let up = envelope(l.stop_max - position, l.brake, l.lookahead_s);
    let down = envelope(position - l.stop_min, l.brake, l.lookahead_s);
    let t = if target.is_finite() { target } else { 0.0 };
    t.min(l.velocity).min(up).max(-l.velocity).max(-down)
}

/// The magnitude of the acceleration towards a velocity `dv` away that can still be ramped
/// down to 0 at `jerk` without overshooting: `a dt + a^2 / (2 jerk) = |dv|`.
fn approach(dv: f64, jerk: f64, dt: f64) -> f64 {
    let dv = dv.abs();
    if jerk.is_infinite() {
        return dv / dt;
    }
    // a = j (-dt + sqrt(dt^2 + 2 dv / j)), in the cancellation-free form.
    2.0 * dv / (dt + (dt * dt + 2.0 * dv / jerk).sqrt())
}

/// One cycle of `dt` seconds: the next commanded state of an axis at `s` driven towards
/// `target` [rad/s].
pub fn step(s: AxisRamp, target: f64, l: &RampLimits, dt: f64) -> AxisRamp {
    let vt = allowed_target(s.position, target, l);
    let dv = vt - s.velocity;
    let want = approach(dv, l.jerk, dt).min(l.acceleration).copysign(dv);
    let jdt = l.jerk * dt;
    let a = want
        .min(s.acceleration + jdt)
        .max(s.acceleration - jdt)
        .clamp(-l.acceleration, l.acceleration);
    let a = if a.is_finite() { a } else { 0.0 };
    let mut v = s.velocity + a * dt;
    // Landing on the target: remove the rounding residue.
    if (v - vt).abs() < 1e-12 {
        v = vt;
    }
    AxisRamp {
        position: s.position + 0.5 * (s.velocity + v) * dt,
        velocity: v,
        acceleration: a,
    }
}

#[cfg(test)]
mod tests;
