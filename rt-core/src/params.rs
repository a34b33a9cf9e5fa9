//! Per-axis parameters of the controller, converted once from the configuration to SI units.
//!
//! Built before the cycle starts; read inside the cycle (plain `Copy` data).

use crate::trajectory::AxisLimits;
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;

/// The joint-space parameters the controller needs every cycle (rad, rad/s, rad/s², Nm, A).
#[derive(Debug, Clone, Copy)]
pub struct JointParams {
    /// Software position limits.
    pub min: [f64; NUM_AXES],
    pub max: [f64; NUM_AXES],
    /// The range a commanded target may lie in: the limits less the safety margin.
    pub reach_min: [f64; NUM_AXES],
    pub reach_max: [f64; NUM_AXES],
    /// Full (unscaled) motion limits per axis.
    pub limits: [AxisLimits; NUM_AXES],
    /// Peak joint torque of each axis (max current x torque per amp).
    pub peak_torque: [f64; NUM_AXES],
    /// Maximum velocity of each axis in the unit of `set_velocities` [deg/s]: the bound the
    /// gateway checks too (`mcm_shared::ranges::max_velocity_deg_s`).
    pub max_velocity_deg_s: [f64; NUM_AXES],
    /// Joint torque per motor ampere.
    pub torque_per_amp: [f64; NUM_AXES],
    pub max_current: [f64; NUM_AXES],
    /// Viscous friction coefficient of each joint [Nm s/rad].
    pub viscous: [f64; NUM_AXES],
    /// Encoder counts per joint radian (the drives' position unit).
    pub counts_per_rad: [f64; NUM_AXES],
    /// Whether the joint has a holding brake (engaged while its drive is not enabled).
    pub brake: [bool; NUM_AXES],
    /// Cycle period [s].
    pub period: f64,
}

impl JointParams {
    pub fn from_config(cfg: &RobotConfig) -> JointParams {
        let a = &cfg.axes;
        // The ranges the gateway checks arguments against, from the same functions.
        let reach = |i| mcm_shared::ranges::reachable_deg(cfg, i);
        let per = |f: &dyn Fn(usize) -> f64| core::array::from_fn(f);
        JointParams {
            min: per(&|i| a[i].min_deg.to_radians()),
            max: per(&|i| a[i].max_deg.to_radians()),
            reach_min: per(&|i| reach(i).0.to_radians()),
            reach_max: per(&|i| reach(i).1.to_radians()),
            limits: core::array::from_fn(|i| AxisLimits {
                velocity: a[i].max_velocity_deg_s.to_radians(),
                acceleration: a[i].max_acceleration_deg_s2.to_radians(),
                jerk: a[i].max_jerk_deg_s3.map(f64::to_radians),
            }),
            peak_torque: per(&|i| mcm_shared::ranges::peak_torque_nm(cfg, i)),
            max_velocity_deg_s: per(&|i| mcm_shared::ranges::max_velocity_deg_s(cfg, i)),
            torque_per_amp: per(&|i| a[i].torque_per_amp()),
            max_current: per(&|i| a[i].max_current_a),
            viscous: per(&|i| a[i].viscous_friction_nm_s_rad),
            counts_per_rad: per(&|i| a[i].counts_per_rad()),
            brake: core::array::from_fn(|i| a[i].brake),
            period: cfg.cycle_period_s(),
        }
    }

    /// Whether `q` lies in the reachable range of `axis`.
    pub fn reachable(&self, axis: usize, q: f64) -> bool {
        q >= self.reach_min[axis] && q <= self.reach_max[axis]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn converts_the_p_rob2_config() {
        let p = JointParams::from_config(&RobotConfig::prob2_default());
        assert!((p.max[1] - 120f64.to_radians()).abs() < 1e-12);
        assert!((p.reach_max[1] - 119f64.to_radians()).abs() < 1e-12);
        assert!((p.limits[0].velocity - 90f64.to_radians()).abs() < 1e-12);
        assert!((p.peak_torque[0] - 129.6).abs() < 1e-9);
        assert!(p.reachable(1, 0.0) && !p.reachable(1, 119.5f64.to_radians()));
        assert_eq!(p.period, 0.005);
    }
}
