//! # mcm-dynamics: rigid-body model of the 6-axis arm (P-Rob2)
//!
//! Two users:
//! - the **controller** uses [`ArmModel`] inside the real-time cycle for gravity and friction
//!   compensation (RELEASE, TORQUE_CONTROL) and for predictions;
//! - the **simulator** (the `mcm-sim` crate) integrates the true state of the simulated arm
//!   with the same model ([`ArmModel::mass_matrix_and_bias`], [`inverse_spd`],
//!   [`solve_friction`]), inside the cycle thread.
//!
//! Runs inside the cycle: every per-call function (`gravity_torques`, `inverse_dynamics`,
//! `mass_matrix`, `forward_dynamics`, `friction_torques`, `flange_pose`, the energies, the
//! solvers) uses fixed-size nalgebra types only, never allocates, never locks and never
//! panics for finite inputs. Only the constructor (`ArmModel::from_config`) runs at start-up.
//!
//! Conventions: standard DH (θᵢ = qᵢ + offsetᵢ), joint i turns about z of frame i−1, link i's
//! centre of mass and inertia are given in DH frame i, the tool is a point mass in frame 6
//! lumped into link 6. Torques are joint-side [Nm]; positive torque accelerates the joint in
//! the positive direction.
//!
//! ```
//! use mcm_dynamics::ArmModel;
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let model = ArmModel::from_config(&cfg);
//! let q = [0.0, 90f64.to_radians(), 0.0, 0.0, 0.0, 0.0];
//! let hold = model.gravity_torques(&q);          // ≈ [0, -65.9, -27.4, 0, -7.9, 0] Nm
//! assert!(hold[1].abs() > 60.0);
//! ```

mod friction;
mod mass;
mod model;
mod payload;
mod rnea;
mod stiction;

pub use friction::{FRICTION_SMOOTHING_RAD_S, JointFriction};
pub use mass::{inverse_spd, solve_spd};
pub use model::{ArmModel, Link};
pub use payload::{
    MAX_CONDITION, MIN_MASS_FOR_CENTER_KG, PayloadError, PayloadEstimate, PayloadEstimator,
};
pub use stiction::solve_friction;

/// Why a configuration could not be turned into an arm model or a simulated arm. Every message
/// names the key, the value found and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DynamicsError {
    /// The configuration has the wrong number of `[[arm.link]]` or `[[axis]]` tables.
    #[error("config `{key}` has {found} entries; exactly 6 are allowed")]
    WrongCount { key: &'static str, found: usize },
    /// A physical parameter is out of range (not finite, negative, zero where > 0 is required).
    #[error("config key `{key}` = {value} is not allowed: {allowed}")]
    Invalid {
        key: String,
        value: f64,
        allowed: &'static str,
    },
}
