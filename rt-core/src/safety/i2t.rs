//! i2t protection: a first-order thermal model per motor (manual: "check that the energy
//! dissipated by each motor stays within safe limits; if exceeded, a reduced maximum motor
//! current applies"). Derating is not an error.
//!
//! Runs inside the cycle: [`I2t::update`] once per cycle, allocation-free and panic-free.
//!
//! The level is the low-pass filtered `I^2 / I_rated^2` with the motor's thermal time constant
//! `tau`, integrated exactly for a current held over `dt`:
//! `level += (1 - exp(-dt/tau)) * (I^2/I_rated^2 - level)`. Running at the rated current the
//! level tends to 1.0 from below. Above [`I2T_DERATE_LEVEL`] the motor's maximum current drops
//! to `i2t_derated_current_a`; it comes back once the level falls below [`I2T_RELEASE_LEVEL`]
//! (hysteresis).
//!
//! ```
//! use mcm_rt_core::safety::{I2t, SafetyParams};
//! let p = SafetyParams::from_config(&mcm_shared::config::RobotConfig::prob2_default());
//! let mut i2t = I2t::new(&p);
//! for _ in 0..200 * 60 {
//!     i2t.update(&[8.0, 0.0, 0.0, 0.0, 0.0, 0.0], 0.005); // one minute at twice rated
//! }
//! assert!(i2t.derated()[0] && !i2t.derated()[1]);
//! assert_eq!(i2t.max_current()[0], p.derated_current[0]);
//! ```

use super::SafetyParams;
use mcm_shared::NUM_AXES;

/// Level above which a motor is derated.
pub const I2T_DERATE_LEVEL: f64 = 1.0;
/// Level below which a derated motor gets its full current back.
pub const I2T_RELEASE_LEVEL: f64 = 0.9;
/// Largest `I^2 / I_rated^2` fed into the filter (a 1000x overcurrent), so that an absurd
/// reading saturates the model instead of making it infinite.
const MAX_INPUT_LEVEL: f64 = 1e6;

/// The i2t state of all six motors, plus the per-motor parameters it needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct I2t {
    level: [f64; NUM_AXES],
    derated: [bool; NUM_AXES],
    rated: [f64; NUM_AXES],
    tau: [f64; NUM_AXES],
    peak: [f64; NUM_AXES],
    derated_current: [f64; NUM_AXES],
}

impl I2t {
    /// Cold motors (level 0, full current).
    pub fn new(params: &SafetyParams) -> I2t {
        I2t {
            level: [0.0; NUM_AXES],
            derated: [false; NUM_AXES],
            rated: params.rated_current,
            tau: params.i2t_tau,
            peak: params.max_current,
            derated_current: params.derated_current,
        }
    }

    /// Advance the model by `dt` seconds with the measured motor currents [A] (sign ignored).
    /// A non-finite current counts as the motor's peak current (the most the drive can give);
    /// a NaN or infinite `dt` settles the level at the present current; `dt <= 0` changes
    /// nothing. The level stays finite whatever the input.
    pub fn update(&mut self, current_a: &[f64; NUM_AXES], dt: f64) {
        for (i, &c) in current_a.iter().enumerate() {
            let c = if c.is_finite() { c } else { self.peak[i] };
            let r = c / self.rated[i];
            let x = r * r;
            let x = if x <= MAX_INPUT_LEVEL {
                x
            } else {
                MAX_INPUT_LEVEL
            }; // also NaN -> max
            let alpha = if dt.is_nan() {
                1.0
            } else if dt <= 0.0 {
                0.0
            } else {
                -(-dt / self.tau[i]).exp_m1()
            };
            let alpha = if (0.0..=1.0).contains(&alpha) {
                alpha
            } else {
                1.0
            };
            self.level[i] += alpha * (x - self.level[i]);
            if self.level[i] > I2T_DERATE_LEVEL {
                self.derated[i] = true;
            } else if self.level[i] < I2T_RELEASE_LEVEL {
                self.derated[i] = false;
            }
        }
    }

    /// Thermal level per motor (1.0 = steady state at rated current).
    pub fn level(&self) -> [f64; NUM_AXES] {
        self.level
    }

    /// Maximum motor current per motor [A]: the derated current where derated, else the peak.
    pub fn max_current(&self) -> [f64; NUM_AXES] {
        core::array::from_fn(|i| {
            if self.derated[i] {
                self.derated_current[i]
            } else {
                self.peak[i]
            }
        })
    }

    /// Which motors are derated.
    pub fn derated(&self) -> [bool; NUM_AXES] {
        self.derated
    }
}

#[cfg(test)]
mod tests;
