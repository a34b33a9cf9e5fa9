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

/// How far from 1 the norm of a quaternion a user gives may be for it to be taken as a unit
/// quaternion (then normalised): the TCP of a tool (`set_tool`, `[arm.tool.tcp]`) and a pose
/// (`inverse_kinematics`, `move_to_pose`).
pub const UNIT_QUATERNION_TOLERANCE: f64 = 1e-3;

/// The quaternion `q` (`[x, y, z, w]`) normalised, when its norm is within
/// [`UNIT_QUATERNION_TOLERANCE`] of 1; `Err` with its norm otherwise (a NaN norm too).
pub fn unit_quaternion(q: [f64; 4]) -> Result<[f64; 4], f64> {
    let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    if (norm - 1.0).abs() <= UNIT_QUATERNION_TOLERANCE {
        Ok(q.map(|x| x / norm))
    } else {
        Err(norm)
    }
}
