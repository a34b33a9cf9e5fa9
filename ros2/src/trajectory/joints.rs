//! The arm's joints as ROS names them, with their limits in SI.

use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;

/// One axis's limits for planning.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisLimits {
    /// The reachable range [rad]: the software limits less the safety margin
    /// (`safety.limit_margin_deg`), the range the core checks every PVT point against.
    pub min: f64,
    pub max: f64,
    /// The same range in degrees, exactly as the core derives it from the configuration.
    pub min_deg: f64,
    pub max_deg: f64,
    /// Largest speed [rad/s] and acceleration [rad/s²] (`max_velocity_deg_s`,
    /// `max_acceleration_deg_s2`).
    pub velocity: f64,
    pub acceleration: f64,
    /// The speed limit as configured [deg/s].
    pub velocity_deg: f64,
}

/// The configuration does not have one axis per joint of the arm.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the configuration has {found} axes; the arm has exactly {NUM_AXES}")]
pub struct AxisCountError {
    pub found: usize,
}

/// The arm's joints in axis order: ROS names (`prefix` + the configuration's axis name) and
/// limits.
#[derive(Debug, Clone, PartialEq)]
pub struct Joints {
    names: [String; NUM_AXES],
    limits: [AxisLimits; NUM_AXES],
}

impl Joints {
    /// The joints of `cfg`, named `prefix` + axis name (e.g. prefix "prob2_" gives
    /// "prob2_base").
    pub fn from_config(cfg: &RobotConfig, prefix: &str) -> Result<Joints, AxisCountError> {
        if cfg.axes.len() != NUM_AXES {
            return Err(AxisCountError {
                found: cfg.axes.len(),
            });
        }
        let a = &cfg.axes;
        Ok(Joints {
            names: std::array::from_fn(|i| format!("{prefix}{}", a[i].name)),
            limits: std::array::from_fn(|i| {
                let (min_deg, max_deg) = mcm_shared::ranges::reachable_deg(cfg, i);
                AxisLimits {
                    min: min_deg.to_radians(),
                    max: max_deg.to_radians(),
                    min_deg,
                    max_deg,
                    velocity: a[i].max_velocity_deg_s.to_radians(),
                    acceleration: a[i].max_acceleration_deg_s2.to_radians(),
                    velocity_deg: a[i].max_velocity_deg_s,
                }
            }),
        })
    }

    /// The ROS joint names, axis 1 first.
    pub fn names(&self) -> &[String; NUM_AXES] {
        &self.names
    }

    /// The name of axis `axis` (0-based).
    pub fn name(&self, axis: usize) -> &str {
        &self.names[axis]
    }

    /// The axis (0-based) of the joint called `name`.
    pub fn axis_of(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// The limits of every axis, axis 1 first.
    pub fn limits(&self) -> &[AxisLimits; NUM_AXES] {
        &self.limits
    }

    /// The known names as a list for messages: "base, shoulder, ...".
    pub fn known(&self) -> String {
        self.names.join(", ")
    }
}
