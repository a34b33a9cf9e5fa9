//! Joint friction model for compensation: Coulomb + viscous, with the Coulomb sign smoothed
//! near zero velocity (`tanh(q̇ / v_ε)`, v_ε = [`FRICTION_SMOOTHING_RAD_S`]).
//!
//! Runs inside the cycle: allocation-free and panic-free.
//!
//! Sign convention: [`ArmModel::friction_torques`] returns the torque the friction **exerts on
//! the joint** (it opposes motion: negative for positive velocity). A controller compensating
//! friction adds [`ArmModel::friction_compensation`] (= −friction_torques) to its command, e.g.
//! in RELEASE `τ = g(q) + α·friction_compensation(q̇)` with α < 1.
//!
//! The simulator (`ArmSim` of the `mcm-sim` crate) does not use the smoothed sign: it models
//! true stiction (see `stiction.rs`), so a joint at rest stays at rest below the Coulomb level.
//!
//! ```
//! use mcm_dynamics::ArmModel;
//! let model = ArmModel::from_config(&mcm_shared::config::RobotConfig::prob2_default());
//! let f = model.friction_torques(&[1.0, 0.0, -1.0, 0.0, 0.0, 0.0]);
//! assert!(f[0] < 0.0 && f[1] == 0.0 && f[2] > 0.0);
//! ```

use super::model::ArmModel;
use mcm_shared::NUM_AXES;

/// Velocity scale of the smoothed Coulomb sign [rad/s] (1 °/s): at 1 °/s the model gives 76 %
/// of the Coulomb level, at 3 °/s 99.5 %. Not in the configuration; a named constant here.
pub const FRICTION_SMOOTHING_RAD_S: f64 = 1.0 * core::f64::consts::PI / 180.0;

/// Friction parameters of one joint (joint side).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointFriction {
    /// Coulomb friction level [Nm] (also the static/break-away level in the simulator).
    pub coulomb: f64,
    /// Viscous coefficient [Nm s/rad].
    pub viscous: f64,
}

impl JointFriction {
    /// Friction torque acting on the joint at velocity `qd` [Nm]; opposes the motion.
    /// A non-finite velocity gives 0.
    pub fn torque(&self, qd: f64) -> f64 {
        if !qd.is_finite() {
            return 0.0;
        }
        -(self.coulomb * (qd / FRICTION_SMOOTHING_RAD_S).tanh() + self.viscous * qd)
    }
}

impl ArmModel {
    /// Friction torques acting on the joints at velocities `qd` [Nm]: smoothed Coulomb plus
    /// viscous, opposing the motion (see the module doc for the sign).
    pub fn friction_torques(&self, qd: &[f64; NUM_AXES]) -> [f64; NUM_AXES] {
        let mut t = [0.0; NUM_AXES];
        for ((t, f), v) in t.iter_mut().zip(&self.friction).zip(qd) {
            *t = f.torque(*v);
        }
        t
    }

    /// Torques a drive must add to cancel the modelled friction (= −`friction_torques`).
    pub fn friction_compensation(&self, qd: &[f64; NUM_AXES]) -> [f64; NUM_AXES] {
        self.friction_torques(qd).map(|t| -t)
    }
}

#[cfg(test)]
mod tests;
