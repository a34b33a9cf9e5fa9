//! The safety figures several users share, converted once from the robot configuration to SI
//! units: the position limits and the stop model (margin, latency, deceleration) that the
//! position-limit and braking checks, the velocity cap and the planners read, and the motors'
//! figures of the i2t model. A check's own figures live with the check
//! ([`super::VelocityLimits::trip`], [`super::FollowingError::band`]).
//!
//! Built outside the cycle (at start, after the configuration was validated); read inside it.

use mcm_shared::NUM_AXES;
use mcm_shared::config::{AxisConfig, RobotConfig};

/// One figure per axis of a configuration: `figure` of each configured axis, `missing` for an
/// axis missing from an unvalidated configuration (a fail-safe value).
pub(super) fn per_axis(
    cfg: &RobotConfig,
    missing: f64,
    figure: impl Fn(&AxisConfig) -> f64,
) -> [f64; NUM_AXES] {
    core::array::from_fn(|i| cfg.axes.get(i).map_or(missing, &figure))
}

/// The shared safety figures in SI units (rad, rad/s, rad/s^2, s, A).
///
/// Built by [`SafetyParams::from_config`] from a validated configuration. Fields are public so
/// that tests and tools can vary one value; inside the controller treat them as read-only.
/// Arrays are indexed by 0-based axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SafetyParams {
    /// Cycle period Ts [s]; the braking check looks one cycle ahead.
    pub cycle_s: f64,
    /// Reaction latency of a stop: `safety.reaction_cycles * Ts` [s].
    pub reaction_s: f64,
    /// Margin kept before each limit by the braking check and the velocity cap [rad].
    pub margin: f64,
    /// Software position limits [rad].
    pub q_min: [f64; NUM_AXES],
    pub q_max: [f64; NUM_AXES],
    /// Nominal maximum velocity [rad/s] (the velocity cap never exceeds it).
    pub v_max: [f64; NUM_AXES],
    /// Maximum acceleration [rad/s^2].
    pub a_max: [f64; NUM_AXES],
    /// Deceleration assumed for a stop: `braking_efficiency * a_max` [rad/s^2].
    pub brake_decel: [f64; NUM_AXES],
    /// Jerk of the stop profile [rad/s^3]; `INFINITY` = second-order stop (constant
    /// deceleration from the first instant), the default. See [`Self::with_jerk_limited_stop`].
    pub stop_jerk: [f64; NUM_AXES],
    /// i2t reference (rated continuous) current [A].
    pub rated_current: [f64; NUM_AXES],
    /// Peak motor current [A] (the current limit when not derated).
    pub max_current: [f64; NUM_AXES],
    /// Current limit while derated by i2t [A].
    pub derated_current: [f64; NUM_AXES],
    /// Thermal time constant of the i2t model [s].
    pub i2t_tau: [f64; NUM_AXES],
}

impl SafetyParams {
    /// Convert a (validated) configuration. Axes missing from an unvalidated configuration
    /// keep fail-safe values (zero range, zero velocity, no braking): every motion trips.
    pub fn from_config(cfg: &RobotConfig) -> SafetyParams {
        let ts = cfg.cycle_period_s();
        let s = &cfg.safety;
        let mut p = SafetyParams {
            cycle_s: ts,
            reaction_s: f64::from(s.reaction_cycles) * ts,
            margin: s.limit_margin_deg.to_radians(),
            q_min: [0.0; NUM_AXES],
            q_max: [0.0; NUM_AXES],
            v_max: [0.0; NUM_AXES],
            a_max: [0.0; NUM_AXES],
            brake_decel: [0.0; NUM_AXES],
            stop_jerk: [f64::INFINITY; NUM_AXES],
            rated_current: [0.0; NUM_AXES],
            max_current: [0.0; NUM_AXES],
            derated_current: [0.0; NUM_AXES],
            i2t_tau: [0.0; NUM_AXES],
        };
        for (i, a) in cfg.axes.iter().take(NUM_AXES).enumerate() {
            p.q_min[i] = a.min_deg.to_radians();
            p.q_max[i] = a.max_deg.to_radians();
            p.v_max[i] = a.max_velocity_deg_s.to_radians();
            p.a_max[i] = a.max_acceleration_deg_s2.to_radians();
            p.brake_decel[i] = s.braking_efficiency * p.a_max[i];
            p.rated_current[i] = a.rated_current_a;
            p.max_current[i] = a.max_current_a;
            p.derated_current[i] = a.i2t_derated_current_a;
            p.i2t_tau[i] = a.i2t_time_constant_s;
        }
        p
    }

    /// The same parameters for a controller whose stops are jerk-limited at each axis's
    /// `max_jerk_deg_s3` (axes without one keep a second-order stop). The braking distance
    /// then grows by `v * a_b / (2 j)` (exact for a trapezoidal deceleration, an upper bound
    /// for a triangular one), i.e. the latency grows by `a_b / (2 j)`.
    pub fn with_jerk_limited_stop(mut self, cfg: &RobotConfig) -> SafetyParams {
        for (i, a) in cfg.axes.iter().take(NUM_AXES).enumerate() {
            if let Some(j) = a.max_jerk_deg_s3 {
                self.stop_jerk[i] = j.to_radians();
            }
        }
        self
    }

    /// Time from the detecting sample until the axis brakes at full `brake_decel`, as seen
    /// by the braking distance: reaction latency plus `a_b / (2 j)` for a jerk-limited stop
    /// [s]. Out-of-range axes get `INFINITY` (every motion trips).
    pub fn braking_latency_s(&self, axis: usize) -> f64 {
        if axis >= NUM_AXES {
            return f64::INFINITY;
        }
        // a / (2 * INFINITY) == 0 for a second-order stop.
        self.reaction_s + self.brake_decel[axis] / (2.0 * self.stop_jerk[axis])
    }
}

#[cfg(test)]
mod tests;
