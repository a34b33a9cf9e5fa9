//! # Safety checks of the real-time core
//!
//! The checks of the manual ("Safety checks") as pure functions over plain data, evaluated by
//! the controller every cycle. **Runs inside the cycle**: every check is allocation-free,
//! lock-free and panic-free; only [`SafetyParams::from_config`] runs outside (once, at start).
//! SI units throughout (rad, rad/s, rad/s^2, s, A); [`Violation::reason`] gives the typed
//! [`Reason`] the core reports, its figures in the user's degrees.
//!
//! | module | check |
//! | --- | --- |
//! | [`limits`] | position limits, velocity limits (`overspeed_factor * max_velocity`) |
//! | [`braking`] | dynamic check (predicted stop position vs limit - margin), velocity cap |
//! | [`following`] | `|commanded - actual|` within the following band |
//! | [`i2t`] | motor heating; reduces the maximum current (not an error) |
//! | [`drive`] | emergency stop, drive connection, drive fault |
//!
//! Which checks apply in which mode is [`ActiveChecks::for_mode`]; [`check_cycle`] runs the
//! active ones in a fixed order and returns the first violation. Non-finite inputs (a NaN
//! position, an infinite velocity) always trip the check that reads them.
//!
//! ```
//! use mcm_rt_core::safety::{self, ActiveChecks, Check, CycleInputs, DriveInputs, SafetyParams};
//! use mcm_shared::{config::RobotConfig, mode::Mode};
//!
//! let params = SafetyParams::from_config(&RobotConfig::prob2_default());
//! let q = [0.0; 6];
//! let mut qd = [0.0; 6];
//! qd[1] = 1.0; // 57 deg/s on axis 2: fine at 0 deg
//! let drives = DriveInputs::all_ok();
//! let inputs = CycleInputs { position: &q, velocity: &qd, commanded: &q, drives: &drives };
//! assert_eq!(safety::check_cycle(&params, ActiveChecks::for_mode(Mode::Pvt), &inputs), Ok(()));
//!
//! let near_limit = [0.0, 118f64.to_radians(), 0.0, 0.0, 0.0, 0.0];
//! let err = safety::check_braking(&params, &near_limit, &qd).unwrap_err();
//! assert_eq!((err.check, err.axis), (Check::BrakingDistance, 1));
//! ```

pub mod braking;
pub mod drive;
pub mod following;
pub mod i2t;
pub mod limits;
mod params;

pub use braking::{
    braking_distance, check_braking, check_braking_accelerating, predicted_stop, velocity_cap,
};
pub use drive::{DriveInputs, DriveStatus, check_drives};
pub use following::check_following_error;
pub use i2t::I2t;
pub use limits::{check_position_limits, check_position_limits_returning, check_velocity_limits};
pub use params::SafetyParams;

use mcm_shared::NUM_AXES;
use mcm_shared::command::Axis;
use mcm_shared::mode::{Mode, RejectCode};
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
    /// `value` = 1, `limit` = 0 (the input is a flag).
    EmergencyStop,
    /// `value` = consecutive missed TPDOs, `limit` = `bus.max_missed_tpdos`.
    DriveDisconnected,
    /// `value` = the drive's EMCY error code (0 if none was received), `limit` = 0.
    DriveFault,
    /// `value` = 0, `limit` = 1 (the axis is not calibrated).
    NotCalibrated,
}

impl Check {
    /// The shared wire code for this check (see `mcm_shared::mode::RejectCode`).
    pub fn reject_code(self) -> RejectCode {
        match self {
            Check::PositionLimit => RejectCode::PositionLimit,
            Check::VelocityLimit => RejectCode::VelocityLimit,
            Check::BrakingDistance => RejectCode::BrakingDistance,
            Check::FollowingError => RejectCode::FollowingError,
            Check::EmergencyStop => RejectCode::EmergencyStop,
            Check::DriveDisconnected => RejectCode::DriveDisconnected,
            Check::DriveFault => RejectCode::DriveFault,
            Check::NotCalibrated => RejectCode::NotCalibrated,
        }
    }

    /// Unit of `value` and `limit` inside the controller ("" for counts and flags).
    pub fn unit(self) -> &'static str {
        match self {
            Check::PositionLimit | Check::BrakingDistance | Check::FollowingError => "rad",
            Check::VelocityLimit => "rad/s",
            _ => "",
        }
    }

    /// Whether `value` and `limit` are angles (rad, rad/s) that users read in degrees.
    pub fn is_angular(self) -> bool {
        matches!(
            self,
            Check::PositionLimit
                | Check::VelocityLimit
                | Check::BrakingDistance
                | Check::FollowingError
        )
    }
}

/// A tripped safety check: which check, which axis (0-based), the value seen and the limit.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error(
    "safety check {} tripped on axis {}: value {} {u}, limit {} {u}",
    .check.reject_code(), .axis + 1, .value, .limit, u = .check.unit()
)]
pub struct Violation {
    pub check: Check,
    /// 0-based axis index (0 for checks that concern no single axis, e.g. the emergency stop).
    pub axis: usize,
    pub value: f64,
    pub limit: f64,
}

impl Violation {
    /// The reason reported for this trip: the check, its axis and its figures in the user's
    /// units (degrees, deg/s; a drive fault's code).
    pub fn reason(&self) -> Reason {
        let axis = Axis::ALL[self.axis.min(NUM_AXES - 1)];
        let (value, limit) = if self.check.is_angular() {
            (rad_to_deg(self.value), rad_to_deg(self.limit))
        } else {
            (self.value, self.limit)
        };
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
            Check::EmergencyStop => Reason::EmergencyStop,
            Check::DriveDisconnected => Reason::DriveDisconnected { axis, also: 0 },
            Check::DriveFault => Reason::DriveFault {
                axis: Some(axis),
                code: value as u16,
            },
            Check::NotCalibrated => Reason::NotCalibrated { axis },
        }
    }
}

/// The per-cycle checks that apply in one operating mode (manual, "Safety checks").
/// i2t protection applies in every mode and is not a violation, so it is not listed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ActiveChecks {
    /// Emergency stop and drive monitoring (all modes).
    pub drives: bool,
    /// Position and velocity limits (RELEASE, TORQUE_CONTROL, PVT).
    pub limits: bool,
    /// Dynamic braking-distance check (RELEASE, TORQUE_CONTROL, PVT).
    pub braking: bool,
    /// Following error (HOLD, PVT).
    pub following: bool,
}

impl ActiveChecks {
    /// The checks the manual prescribes for `mode`. OFF, ERROR and CALIBRATION monitor the
    /// drives only (positions are raw encoder values during a calibration's searches; its move
    /// back: [`ActiveChecks::for_calibration_return`]).
    pub fn for_mode(mode: Mode) -> ActiveChecks {
        let motion = matches!(
            mode,
            Mode::Release | Mode::TorqueControl | Mode::Pvt | Mode::VelocityControl
        );
        ActiveChecks {
            drives: true,
            limits: motion,
            braking: motion,
            following: matches!(mode, Mode::Hold | Mode::Pvt | Mode::VelocityControl),
        }
    }

    /// The checks of a calibration's move back to zero, a planned move whose axes are all
    /// calibrated by then (the offsets the searches found are in force): the following error.
    /// Without it an axis whose calibration an obstacle fooled, its gravity feed-forward
    /// computed for the wrong angle, ran away from that move unwatched. Not the position
    /// limits: an axis calibrated against its stop starts the move beyond its software limit,
    /// and the move was planned to end inside them; nor the velocity limit or the braking
    /// distance, which an axis that follows its plan cannot break.
    pub fn for_calibration_return() -> ActiveChecks {
        ActiveChecks {
            drives: true,
            limits: false,
            braking: false,
            following: true,
        }
    }
}

/// Whether entering `mode` requires every axis to be calibrated (RELEASE, TORQUE_CONTROL, PVT);
/// use [`check_calibrated`] then.
pub fn requires_calibration(mode: Mode) -> bool {
    matches!(
        mode,
        Mode::Release | Mode::TorqueControl | Mode::Pvt | Mode::VelocityControl
    )
}

/// `Err` naming the first axis that is not calibrated.
pub fn check_calibrated(calibrated: &[bool; NUM_AXES]) -> Result<(), Violation> {
    match calibrated.iter().position(|c| !c) {
        Some(axis) => Err(Violation {
            check: Check::NotCalibrated,
            axis,
            value: 0.0,
            limit: 1.0,
        }),
        None => Ok(()),
    }
}

/// What [`check_cycle`] reads, all SI.
#[derive(Clone, Copy, Debug)]
pub struct CycleInputs<'a> {
    /// Measured joint positions [rad].
    pub position: &'a [f64; NUM_AXES],
    /// Joint velocities for the limit and braking checks [rad/s]. Motion-and-dynamics 5.6
    /// suggests the larger (toward the limit) of commanded and measured + tracking bound.
    pub velocity: &'a [f64; NUM_AXES],
    /// Commanded joint positions [rad] (following error).
    pub commanded: &'a [f64; NUM_AXES],
    /// Drive and emergency-stop inputs.
    pub drives: &'a DriveInputs,
}

/// Run the `active` checks in order: drives (emergency stop, disconnected, fault), position
/// limits, velocity limits, braking distance, following error. Returns the first violation.
pub fn check_cycle(
    params: &SafetyParams,
    active: ActiveChecks,
    inputs: &CycleInputs<'_>,
) -> Result<(), Violation> {
    if active.drives {
        check_drives(params, inputs.drives)?;
    }
    if active.limits {
        check_position_limits(params, inputs.position)?;
        check_velocity_limits(params, inputs.velocity)?;
    }
    if active.braking {
        check_braking(params, inputs.position, inputs.velocity)?;
    }
    if active.following {
        check_following_error(params, inputs.commanded, inputs.position)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests;
