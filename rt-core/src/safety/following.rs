//! Following error: the actual position must stay within a band around the commanded one
//! ([`FollowingError`], the last per-cycle check: in HOLD, PVT and VELOCITY_CONTROL, in a
//! calibration's move back to zero, and for the axes a calibration's searches do not cover).
//! Also catches collisions and blocked axes.
//!
//! Runs inside the cycle (pure, allocation-free, panic-free); [`FollowingError::from_config`]
//! runs once at start. An error exactly equal to the band is allowed; NaN or infinite positions
//! trip.
//!
//! Parameter: the band, `axis.following_error_deg` (`0 < x <=`
//! [`FOLLOWING_ERROR_MAX_DEG`](mcm_shared::config::FOLLOWING_ERROR_MAX_DEG), checked when the
//! configuration is read).
//!
//! ```
//! use mcm_rt_core::safety::FollowingError;
//! use mcm_shared::reply::Reason;
//! let f = FollowingError::from_config(&mcm_shared::config::RobotConfig::prob2_default());
//! let cmd = [0.0; 6];
//! let mut act = [0.0; 6];
//! act[2] = -2.5f64.to_radians(); // band is 2 deg
//! let v = f.check(&cmd, &act).unwrap_err();
//! assert_eq!(v.axis, 2);
//! let Reason::FollowingError { error_deg, band_deg, .. } = v.reason() else { panic!() };
//! assert!((error_deg - 2.5).abs() < 1e-9 && (band_deg - 2.0).abs() < 1e-9);
//! ```

use super::{
    Calibrating, Check, CycleCheck, CycleInputs, SafetyParams, Situation, Violation, per_axis,
};
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::Mode;

/// The following error of the measured positions against the commanded ones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowingError {
    /// The band per axis [rad] (0 for an axis missing from an unvalidated configuration: every
    /// error trips).
    pub band: [f64; NUM_AXES],
}

impl FollowingError {
    /// The bands of a (validated) configuration.
    pub fn from_config(cfg: &RobotConfig) -> FollowingError {
        FollowingError {
            band: per_axis(cfg, 0.0, |a| a.following_error_deg.to_radians()),
        }
    }

    /// `Err` for the first axis with `|commanded - actual| > band` (or not finite);
    /// `value` = `|commanded - actual|` [rad], `limit` = the band [rad].
    pub fn check(
        &self,
        commanded: &[f64; NUM_AXES],
        actual: &[f64; NUM_AXES],
    ) -> Result<(), Violation> {
        for (i, (&c, &a)) in commanded.iter().zip(actual).enumerate() {
            let err = (c - a).abs();
            // inf - inf is NaN; one infinite side gives inf.
            if err.is_nan() || err > self.band[i] {
                return Err(Violation {
                    check: Check::FollowingError,
                    axis: i,
                    value: err,
                    limit: self.band[i],
                });
            }
        }
        Ok(())
    }
}

impl CycleCheck for FollowingError {
    const ID: Check = Check::FollowingError;

    fn runs(&self, now: &Situation) -> bool {
        // In a calibration's searches, the axes they do not cover hold where they are (the
        // searching axes' commanded position is their measured one). In its move back to zero,
        // an axis whose calibration an obstacle fooled, its gravity feed-forward computed for
        // the wrong angle, would otherwise run away from that move unwatched (the position
        // limits do not run there: an axis calibrated against its stop starts the move beyond
        // its software limit, and the move was planned to end inside them).
        now.calibrating != Calibrating::No
            || matches!(now.mode, Mode::Hold | Mode::Pvt | Mode::VelocityControl)
    }

    fn verdict(
        &mut self,
        _shared: &SafetyParams,
        inputs: &CycleInputs<'_>,
    ) -> Result<(), Violation> {
        self.check(inputs.commanded, inputs.position)
    }
}

#[cfg(test)]
mod tests;
