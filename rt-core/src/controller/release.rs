//! RELEASE's soft speed limit: a damping torque that is zero at ordinary hand-guiding speeds
//! and rises near each joint's velocity limit, so that a firm push is slowed instead of
//! tripping the hard `velocity_limit` check (which stays as the last resort).
//!
//! Runs inside the cycle: pure `f64` arithmetic on fixed-size arrays, no allocation.
//!
//! # The damping
//! For an axis with velocity limit `v_max` (`axis.max_velocity_deg_s`), the damping starts at
//! `v_on = safety.release_speed_onset x v_max`. Over the first half of the band from `v_on`
//! to `v_max` it blends in quadratically, then it is linear with slope `b` (so the torque is
//! continuous and so is its slope):
//!
//! ```text
//! x = |v| - v_on,  w = (v_max - v_on) / 2
//! tau = 0                      x <= 0
//!       b x^2 / (2 w)          0 < x < w
//!       b (x - w / 2)          x >= w
//! ```
//!
//! opposing the velocity and capped at the drive's peak torque. At `v_max` it resists with
//! `1.5 b w`. The slope `b` is `safety.release_speed_damping x J / Ts`, where `J` is the
//! inertia the axis shows to its own torque at the current pose (`1 / (M^-1)_ii`, armature
//! included) and `Ts` the cycle period: the share of the velocity a cycle removes. It must
//! stay well below 1 because the velocity is measured two to three cycles before the torque
//! acts (the bound is 0.4).

use mcm_dynamics::ArmModel;
use mcm_dynamics::inverse_spd;
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;

/// The soft speed limit of one axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SoftSpeedLimit {
    /// Velocity at which the damping starts [rad/s].
    pub onset: f64,
    /// The axis's velocity limit [rad/s].
    pub limit: f64,
}

impl SoftSpeedLimit {
    /// The damping torque [Nm] at velocity `v` [rad/s] with full slope `slope` [Nm s/rad],
    /// capped at `tau_max` [Nm]: opposes `v`, zero up to the onset, continuous. A velocity
    /// that is not finite gets no damping (the velocity check trips on it).
    pub fn torque(&self, v: f64, slope: f64, tau_max: f64) -> f64 {
        let x = v.abs() - self.onset;
        let usable = v.is_finite() && x > 0.0 && slope.is_finite() && slope > 0.0 && tau_max > 0.0;
        if !usable {
            return 0.0;
        }
        let w = 0.5 * (self.limit - self.onset).max(f64::MIN_POSITIVE);
        let m = if x < w {
            slope * x * x / (2.0 * w)
        } else {
            slope * (x - 0.5 * w)
        };
        -m.min(tau_max).copysign(v)
    }

    /// The torque the damping resists with at the velocity limit, for slope `slope`.
    pub fn resisting_at_limit(&self, slope: f64) -> f64 {
        0.75 * slope * (self.limit - self.onset)
    }
}

/// The soft speed limits of an arm, from its configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReleaseParams {
    pub axes: [SoftSpeedLimit; NUM_AXES],
    /// `safety.release_speed_damping`.
    pub share: f64,
}

impl ReleaseParams {
    pub fn from_config(cfg: &RobotConfig) -> ReleaseParams {
        let s = &cfg.safety;
        ReleaseParams {
            axes: core::array::from_fn(|i| {
                let limit = cfg.axes[i].max_velocity_deg_s.to_radians();
                SoftSpeedLimit {
                    onset: s.release_speed_onset * limit,
                    limit,
                }
            }),
            share: s.release_speed_damping,
        }
    }

    /// The damping torques at pose `q`, velocities `qd`, each capped at `tau_max`.
    pub fn torques(
        &self,
        model: &ArmModel,
        q: &[f64; NUM_AXES],
        qd: &[f64; NUM_AXES],
        period: f64,
        tau_max: &[f64; NUM_AXES],
    ) -> [f64; NUM_AXES] {
        // The pose's inertia is needed only when an axis is beyond its onset.
        if (0..NUM_AXES).all(|i| qd[i].abs() <= self.axes[i].onset) {
            return [0.0; NUM_AXES];
        }
        let slopes = damping_slopes(model, q, self.share, period);
        core::array::from_fn(|i| self.axes[i].torque(qd[i], slopes[i], tau_max[i]))
    }
}

/// The damping slope of every axis at pose `q`: `share x J_i / period` [Nm s/rad], with
/// `J_i = 1 / (M(q)^-1)_ii`.
pub fn damping_slopes(
    model: &ArmModel,
    q: &[f64; NUM_AXES],
    share: f64,
    period: f64,
) -> [f64; NUM_AXES] {
    let inv = inverse_spd(&model.mass_matrix(q));
    core::array::from_fn(|i| {
        let j = 1.0 / inv[(i, i)];
        if j.is_finite() && j > 0.0 {
            share * j / period
        } else {
            0.0
        }
    })
}

#[cfg(test)]
mod tests;
