//! Unit conventions.
//!
//! Users (JSON, HMI, config file, IPC samples) speak degrees, degrees/s, degrees/s^2, newton-metres
//! and amperes, as the manual says. Inside the controller everything is SI: radians, rad/s, rad/s^2.
//! Conversion happens once, at the boundaries of the real-time core:
//!
//! - the configuration, when the core builds its parameters at start-up (`params`, the safety
//!   parameters, the calibration settings, the drive scaling of the CANopen master);
//! - a command, where the controller takes the typed request in (`controller/commands.rs`);
//! - the published state, in the one function that composes it (`rt-core/src/publish.rs`),
//!   and the figures of a refusal or safety error, where its `Reason` is built.

/// Degrees to radians.
#[inline]
pub fn deg_to_rad(deg: f64) -> f64 {
    deg.to_radians()
}

/// Radians to degrees.
#[inline]
pub fn rad_to_deg(rad: f64) -> f64 {
    rad.to_degrees()
}

/// Convert six values from degrees to radians.
#[inline]
pub fn deg_to_rad6(v: &[f64; 6]) -> [f64; 6] {
    v.map(deg_to_rad)
}

/// Convert six values from radians to degrees.
#[inline]
pub fn rad_to_deg6(v: &[f64; 6]) -> [f64; 6] {
    v.map(rad_to_deg)
}

#[cfg(test)]
mod tests;
