//! # Safety checks of the real-time core
//!
//! The checks of the manual ("Safety checks") as pure functions over plain data. **Runs inside
//! the cycle**: every check is allocation-free, lock-free and panic-free; only
//! [`CycleChecks::from_config`] and [`SafetyParams::from_config`] run outside (once, at start).
//! SI units throughout (rad, rad/s, rad/s^2, s, A); [`Violation::reason`] gives the typed
//! [`Reason`] the core reports, its figures in the user's degrees.
//!
//! Each per-cycle check is one file that implements [`CycleCheck`] (`check.rs`: when it runs,
//! what it reads, when it trips and what it names); [`CycleChecks`] holds them and runs them in
//! their order every cycle, the first violation being the one reported
//! (`docs/architecture.md`, "How to add a safety check").
//!
//! | module | check |
//! | --- | --- |
//! | [`limits`] | position limits (beyond one only moving back), velocity limits |
//! | [`braking`] | dynamic check (predicted stop position vs limit - margin), velocity cap |
//! | [`following`] | `|commanded - actual|` within the following band |
//! | [`i2t`] | motor heating; reduces the maximum current (not an error) |
//!
//! Not per-cycle checks of the measured state: the emergency stop's press and the drives'
//! connection and faults, which the CANopen master reports (`controller/trips.rs`); the torque
//! command judged before it is sent ([`check_braking_accelerating`], `controller/motion.rs`);
//! the overload of a derated axis (`controller/overload.rs`).
//!
//! ```
//! use mcm_rt_core::safety::{Calibrating, Check, CycleChecks, CycleInputs, Situation};
//! use mcm_shared::{config::RobotConfig, mode::Mode};
//!
//! let mut checks = CycleChecks::from_config(&RobotConfig::prob2_default());
//! let now = Situation {
//!     mode: Mode::Pvt,
//!     calibrating: Calibrating::No,
//!     planned_motion: false,
//!     procedure: false,
//!     disabled: None,
//! };
//! let q = [0.0; 6];
//! let mut qd = [0.0; 6];
//! qd[1] = 1.0; // 57 deg/s on axis 2: fine at 0 deg
//! let inputs = CycleInputs { position: &q, velocity: &qd, commanded: &q };
//! assert_eq!(checks.run(&now, &inputs), Ok(()));
//!
//! let near_limit = [0.0, 118f64.to_radians(), 0.0, 0.0, 0.0, 0.0];
//! let inputs = CycleInputs { position: &near_limit, commanded: &near_limit, ..inputs };
//! let err = checks.run(&now, &inputs).unwrap_err();
//! assert_eq!((err.check, err.axis), (Check::BrakingDistance, 1));
//! ```

pub mod braking;
mod check;
pub mod following;
pub mod i2t;
pub mod limits;
mod params;

pub use braking::{
    BrakingDistance, braking_distance, check_braking, check_braking_accelerating, predicted_stop,
    velocity_cap,
};
pub use check::{Calibrating, CycleCheck, CycleInputs, Situation};
pub use following::FollowingError;
pub use i2t::I2t;
pub use limits::{PositionLimits, VelocityLimits, check_position_limits_returning};
pub use params::SafetyParams;
use params::per_axis;

use mcm_shared::NUM_AXES;
use mcm_shared::command::Axis;
use mcm_shared::config::RobotConfig;
use mcm_shared::reply::Reason;
use mcm_shared::units::rad_to_deg;

/// Which safety check tripped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Check {
    /// `value` = position [rad], `limit` = the limit passed [rad].
    PositionLimit,
    /// `value` = velocity [rad/s], `limit` = the trip velocity with the sign of `value` [rad/s].
    VelocityLimit,
    /// `value` = predicted stop position [rad], `limit` = limit -/+ margin [rad].
    BrakingDistance,
    /// `value` = |commanded - actual| [rad], `limit` = the band [rad].
    FollowingError,
}

impl Check {
    /// Unit of `value` and `limit` inside the controller.
    pub fn unit(self) -> &'static str {
        match self {
            Check::PositionLimit | Check::BrakingDistance | Check::FollowingError => "rad",
            Check::VelocityLimit => "rad/s",
        }
    }
}

/// A tripped safety check: which check, which axis (0-based), the value seen and the limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Violation {
    pub check: Check,
    /// 0-based axis index.
    pub axis: usize,
    pub value: f64,
    pub limit: f64,
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let u = self.check.unit();
        write!(
            f,
            "safety check {} tripped on axis {}: value {} {u}, limit {} {u}",
            self.reason().code(),
            self.axis + 1,
            self.value,
            self.limit
        )
    }
}

impl std::error::Error for Violation {}

impl Violation {
    /// The reason reported for this trip: the check, its axis and its figures in the user's
    /// units (degrees, deg/s).
    pub fn reason(&self) -> Reason {
        let axis = Axis::ALL[self.axis.min(NUM_AXES - 1)];
        let (value, limit) = (rad_to_deg(self.value), rad_to_deg(self.limit));
        match self.check {
            Check::PositionLimit => Reason::PositionLimit {
                axis,
                position_deg: value,
                limit_deg: limit,
            },
            Check::VelocityLimit => Reason::VelocityLimit {
                axis,
                velocity_deg_s: value,
                limit_deg_s: limit,
            },
            Check::BrakingDistance => Reason::BrakingDistance {
                axis,
                stop_deg: value,
                limit_deg: limit,
            },
            Check::FollowingError => Reason::FollowingError {
                axis,
                error_deg: value,
                band_deg: limit,
            },
        }
    }
}

/// The per-cycle safety checks with their parameters, in the order the controller runs them:
/// position limits, velocity limits, braking distance, following error. The first violation is
/// the one reported.
#[derive(Clone, Copy, Debug)]
pub struct CycleChecks {
    /// The figures the checks share (position limits, the stop model) in SI units.
    params: SafetyParams,
    position: PositionLimits,
    velocity: VelocityLimits,
    braking: BrakingDistance,
    following: FollowingError,
}

impl CycleChecks {
    /// Every check with its parameters from a (validated) configuration. Outside the cycle.
    pub fn from_config(cfg: &RobotConfig) -> CycleChecks {
        CycleChecks {
            params: SafetyParams::from_config(cfg),
            position: PositionLimits,
            velocity: VelocityLimits::from_config(cfg),
            braking: BrakingDistance,
            following: FollowingError::from_config(cfg),
        }
    }

    /// Run the checks that run in `now`, in order; the first violation.
    pub fn run(&mut self, now: &Situation, inputs: &CycleInputs<'_>) -> Result<(), Violation> {
        let p = &self.params;
        check::run_one(&mut self.position, p, now, inputs)?;
        check::run_one(&mut self.velocity, p, now, inputs)?;
        check::run_one(&mut self.braking, p, now, inputs)?;
        check::run_one(&mut self.following, p, now, inputs)
    }
}

#[cfg(test)]
mod tests;
