//! Roll, pitch and yaw for people (the HMI and the pendant show orientations so; the protocol
//! takes unit quaternions `[x, y, z, w]`). The convention is the URDF's `rpy`: fixed axes X, Y,
//! Z, i.e. R = Rz(yaw) · Ry(pitch) · Rx(roll): first roll about the base's (or flange's) x
//! axis, then pitch about its y axis, then yaw about its z axis, each about the fixed frame's
//! axis. Angles in degrees. Not used inside the real-time cycle (it may be: no allocation).

use nalgebra::UnitQuaternion;

/// The unit quaternion `[x, y, z, w]` (`w >= 0`) of roll, pitch and yaw [deg].
pub fn quaternion_from_rpy_deg(rpy_deg: [f64; 3]) -> [f64; 4] {
    let [r, p, y] = rpy_deg.map(f64::to_radians);
    let q = UnitQuaternion::from_euler_angles(r, p, y);
    let c = q.coords;
    let s = if c.w < 0.0 { -1.0 } else { 1.0 };
    [s * c.x, s * c.y, s * c.z, s * c.w]
}

/// Roll, pitch and yaw [deg] of the unit quaternion `[x, y, z, w]`: roll and yaw in
/// [-180, 180], pitch in [-90, 90]. At pitch ±90° roll and yaw turn about the same line: the
/// rotation is kept, not how it was split between them.
pub fn rpy_deg_from_quaternion(q: [f64; 4]) -> [f64; 3] {
    let (r, p, yaw) = crate::rotation(q).euler_angles();
    [r, p, yaw].map(f64::to_degrees)
}

#[cfg(test)]
mod tests;
