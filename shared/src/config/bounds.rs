//! The bounds of the safety parameters: each has a lower and an upper bound that keeps its
//! check meaningful (a value outside switches the check off in effect, or makes it refuse
//! everything). Refused at start with the key, the value and the range; the table in
//! `docs/safety.md` lists them. Checked by [`super::RobotConfig::validate`].

use super::{AxisConfig, BusBackend, ConfigError, RobotConfig, invalid};

/// `safety.limit_margin_deg`: at most this [deg] (a larger margin hides the limits' meaning).
pub const LIMIT_MARGIN_MAX_DEG: f64 = 5.0;
/// `safety.braking_efficiency`: the share of the maximum deceleration the braking check
/// assumes, at least this (below, it refuses nearly every motion) and at most 1.
pub const BRAKING_EFFICIENCY_MIN: f64 = 0.3;
/// `safety.reaction_cycles`: at least one cycle (a stop always takes one), at most this
/// much time of cycles [s].
pub const REACTION_MAX_S: f64 = 0.5;
/// `safety.overspeed_factor`: 1 (trip at the limit) to this (50 % over the limit).
pub const OVERSPEED_FACTOR_MAX: f64 = 1.5;
/// `safety.release_speed_onset`: this to [`RELEASE_SPEED_ONSET_MAX`] (damping that starts
/// lower slows ordinary hand guiding; higher leaves no room to slow a push before the limit).
pub const RELEASE_SPEED_ONSET_MIN: f64 = 0.2;
pub const RELEASE_SPEED_ONSET_MAX: f64 = 0.8;
/// `safety.release_speed_damping`: this to [`RELEASE_SPEED_DAMPING_MAX`] (less does not slow
/// a push in effect; more than 0.4 of what a cycle can carry is expected, not measured, to make
/// the damping ring with the two to three cycles of delay between the measured velocity and
/// the torque).
pub const RELEASE_SPEED_DAMPING_MIN: f64 = 0.05;
pub const RELEASE_SPEED_DAMPING_MAX: f64 = 0.4;
/// `safety.flight_recorder_seconds`: this to [`FLIGHT_RECORDER_MAX_S`] [s].
pub const FLIGHT_RECORDER_MIN_S: f64 = 1.0;
pub const FLIGHT_RECORDER_MAX_S: f64 = 60.0;
/// `axis.following_error_deg`: above 0, at most this [deg].
pub const FOLLOWING_ERROR_MAX_DEG: f64 = 10.0;
/// `axis.max_velocity_deg_s`: above 0, at most this [deg/s].
pub const VELOCITY_MAX_DEG_S: f64 = 400.0;
/// `axis.max_acceleration_deg_s2`: above 0, at most this [deg/s^2].
pub const ACCELERATION_MAX_DEG_S2: f64 = 5000.0;
/// `axis.max_jerk_deg_s3`: above 0, at most this [deg/s^3].
pub const JERK_MAX_DEG_S3: f64 = 100_000.0;
/// `axis.max_current_a`: at most this multiple of `rated_current_a`.
pub const PEAK_TO_RATED_MAX: f64 = 4.0;
/// `axis.calibration.tolerance_deg`: this to [`CALIBRATION_TOLERANCE_MAX_DEG`] [deg]. Below,
/// the stops' own compliance fails good calibrations; above, a contact in free air after the
/// 2-degree back-off could pass.
pub const CALIBRATION_TOLERANCE_MIN_DEG: f64 = 0.1;
pub const CALIBRATION_TOLERANCE_MAX_DEG: f64 = 1.0;
/// `axis.i2t_time_constant_s`: this to [`I2T_TIME_CONSTANT_MAX_S`] [s].
pub const I2T_TIME_CONSTANT_MIN_S: f64 = 1.0;
pub const I2T_TIME_CONSTANT_MAX_S: f64 = 600.0;

/// `v` within `lo..=hi` (finite; NaN fails), else the refusal naming `key` and the range.
fn within(key: impl Into<String>, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), ConfigError> {
    if v.is_finite() && v >= lo && v <= hi {
        return Ok(());
    }
    Err(invalid(key, v, format!("{lo}..={hi}{unit}")))
}

/// `v` within `0 < v <= hi` (finite; NaN fails), else the refusal naming `key` and the range.
fn positive_upto(key: impl Into<String>, v: f64, hi: f64, what: &str) -> Result<(), ConfigError> {
    if v.is_finite() && v > 0.0 && v <= hi {
        return Ok(());
    }
    Err(invalid(key, v, format!("0 < x <= {hi}{what}")))
}

impl RobotConfig {
    /// The bounds of `[safety]`, of `bus.interface` for SocketCAN, and of each axis's safety
    /// figures.
    pub(super) fn validate_bounds(&self) -> Result<(), ConfigError> {
        let s = &self.safety;
        within(
            "safety.limit_margin_deg",
            s.limit_margin_deg,
            0.0,
            LIMIT_MARGIN_MAX_DEG,
            " deg",
        )?;
        within(
            "safety.braking_efficiency",
            s.braking_efficiency,
            BRAKING_EFFICIENCY_MIN,
            1.0,
            "",
        )?;
        let max_cycles = ((REACTION_MAX_S * f64::from(self.cycle.rate_hz)).floor() as u32).max(1);
        if !(1..=max_cycles).contains(&s.reaction_cycles) {
            return Err(invalid(
                "safety.reaction_cycles",
                s.reaction_cycles,
                format!(
                    "1..={max_cycles} cycles (at most {REACTION_MAX_S} s at cycle.rate_hz = {})",
                    self.cycle.rate_hz
                ),
            ));
        }
        within(
            "safety.overspeed_factor",
            s.overspeed_factor,
            1.0,
            OVERSPEED_FACTOR_MAX,
            "",
        )?;
        within(
            "safety.release_speed_onset",
            s.release_speed_onset,
            RELEASE_SPEED_ONSET_MIN,
            RELEASE_SPEED_ONSET_MAX,
            "",
        )?;
        within(
            "safety.release_speed_damping",
            s.release_speed_damping,
            RELEASE_SPEED_DAMPING_MIN,
            RELEASE_SPEED_DAMPING_MAX,
            "",
        )?;
        within(
            "safety.flight_recorder_seconds",
            s.flight_recorder_seconds,
            FLIGHT_RECORDER_MIN_S,
            FLIGHT_RECORDER_MAX_S,
            " s",
        )?;
        if s.flight_recorder_dir.trim().is_empty() {
            return Err(invalid(
                "safety.flight_recorder_dir",
                format!("{:?}", s.flight_recorder_dir),
                "a directory path (mcm-rt creates it and checks it can write there at start)",
            ));
        }
        if self.bus.backend == BusBackend::Socketcan && self.bus.interface.trim().is_empty() {
            return Err(invalid(
                "bus.interface",
                "\"\"",
                "a SocketCAN interface name (e.g. can0) when bus.backend = \"socketcan\"",
            ));
        }
        Ok(())
    }
}

impl AxisConfig {
    /// The upper bounds of one axis's safety figures (their lower bounds and finiteness are
    /// checked by `AxisConfig::validate` first).
    pub(super) fn validate_bounds(&self, key: &str) -> Result<(), ConfigError> {
        positive_upto(
            format!("{key}.following_error_deg"),
            self.following_error_deg,
            FOLLOWING_ERROR_MAX_DEG,
            " deg",
        )?;
        positive_upto(
            format!("{key}.max_velocity_deg_s"),
            self.max_velocity_deg_s,
            VELOCITY_MAX_DEG_S,
            " deg/s",
        )?;
        positive_upto(
            format!("{key}.max_acceleration_deg_s2"),
            self.max_acceleration_deg_s2,
            ACCELERATION_MAX_DEG_S2,
            " deg/s^2",
        )?;
        if let Some(j) = self.max_jerk_deg_s3 {
            positive_upto(
                format!("{key}.max_jerk_deg_s3"),
                j,
                JERK_MAX_DEG_S3,
                " deg/s^3",
            )?;
        }
        let peak = PEAK_TO_RATED_MAX * self.rated_current_a;
        positive_upto(
            format!("{key}.max_current_a"),
            self.max_current_a,
            peak,
            &format!(" A ({PEAK_TO_RATED_MAX} x {key}.rated_current_a)"),
        )?;
        positive_upto(
            format!("{key}.i2t_derated_current_a"),
            self.i2t_derated_current_a,
            self.rated_current_a,
            &format!(" A ({key}.rated_current_a: the motor must cool)"),
        )?;
        within(
            format!("{key}.i2t_time_constant_s"),
            self.i2t_time_constant_s,
            I2T_TIME_CONSTANT_MIN_S,
            I2T_TIME_CONSTANT_MAX_S,
            " s",
        )?;
        positive_upto(
            format!("{key}.calibration.search_velocity_deg_s"),
            self.calibration.search_velocity_deg_s,
            self.max_velocity_deg_s,
            &format!(" deg/s ({key}.max_velocity_deg_s)"),
        )?;
        positive_upto(
            format!("{key}.calibration.search_current_a"),
            self.calibration.search_current_a,
            self.max_current_a,
            &format!(" A ({key}.max_current_a)"),
        )?;
        within(
            format!("{key}.calibration.tolerance_deg"),
            self.calibration.tolerance_deg,
            CALIBRATION_TOLERANCE_MIN_DEG,
            CALIBRATION_TOLERANCE_MAX_DEG,
            " deg",
        )?;
        Ok(())
    }
}
