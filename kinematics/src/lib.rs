//! # mcm-kinematics: where the arm's tool is, and how to get it somewhere
//!
//! The kinematics of the six-axis arm from the configuration's standard DH links
//! (`[[arm.link]]`), for the core's cycle, the gateway's checks and the clients alike:
//!
//! - [`Kinematics::flange_pose`] and [`Kinematics::tcp_pose`]: forward kinematics of the flange
//!   (DH frame 6) and of the TCP (the flange times the tool's TCP transform);
//! - [`Kinematics::tcp_jacobian`]: the geometric Jacobian at the TCP (linear and angular
//!   velocity in base-frame axes);
//! - [`Kinematics::inverse`]: inverse kinematics with every solution (up to
//!   [`MAX_SOLUTIONS`]: shoulder, elbow and wrist each on one side or the other) within the
//!   axes' reachable ranges, the nearest to a seed first;
//! - [`Kinematics::singularities`]: how near the wrist, elbow and shoulder singularities a
//!   configuration is, and [`SingularityMargins`] to call it near;
//! - [`LinePlan`]: the TCP on a straight line (`move_linear`), the whole path checked before
//!   anything moves, time-scaled within the axes' limits ([`line`]).
//!
//! Frames: the base frame is DH frame 0 (z up, along axis 1), the flange frame DH frame 6,
//! the TCP frame the flange frame times [`Kinematics::tcp`]. Units: metres and radians (the
//! protocol's degrees are converted at its edge, `mcm_shared::units`).
//!
//! Only [`Kinematics::from_config`] checks the arm ([`KinematicsError`]: the analytic solver
//! needs a spherical wrist and the shape described in [`shape`]); every other function uses
//! fixed-size nalgebra types and `heapless` storage, never allocates, locks or logs, and
//! never panics: it may run in the control cycle.
//!
//! ```
//! use mcm_kinematics::Kinematics;
//! use mcm_shared::config::RobotConfig;
//! use nalgebra::Isometry3;
//!
//! let mut kin = Kinematics::from_config(&RobotConfig::prob2_default()).unwrap();
//! // A tool 15 cm long along the flange's z axis.
//! kin.set_tcp(Isometry3::translation(0.0, 0.0, 0.15)).unwrap();
//! let q = [0.1, 0.4, -0.3, 0.2, 0.9, -0.5];
//! let pose = kin.tcp_pose(&q);
//! let solutions = kin.inverse(&pose, &q).unwrap();
//! assert!(solutions.len() <= mcm_kinematics::MAX_SOLUTIONS);
//! // The seed's own configuration comes back first ...
//! let first = solutions[0].q;
//! assert!(first.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9));
//! // ... and every solution puts the TCP where it was asked to be.
//! for s in &solutions {
//!     let p = kin.tcp_pose(&s.q);
//!     assert!((p.translation.vector - pose.translation.vector).norm() < 1e-9);
//! }
//! ```

mod dh;
mod forward;
mod inverse;
mod limits;
pub mod line;
mod rpy;
pub mod shape;
mod singularity;

pub use dh::Dh;
pub use inverse::{Branch, IkError, MAX_SOLUTIONS, Side, Solution, Solutions};
pub use limits::{AxisRange, LIMIT_TOLERANCE_RAD, travel_time};
pub use line::{JointLimits, LineError, LinePlan, LineSample, LineTarget};
pub use rpy::{quaternion_from_rpy_deg, rpy_deg_from_quaternion};
pub use shape::KinematicsError;
pub use singularity::{Near, Singularities, SingularityMargins};

use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;
use mcm_shared::ranges::reachable_deg;
use mcm_shared::tool::Tcp;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use shape::Shape;

const N: usize = NUM_AXES;

/// The arm's kinematics: its six links, the axes' reachable ranges and maximum velocities, and
/// the active TCP. Plain data (no heap): cheap to copy into the cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    links: [Dh; N],
    shape: Shape,
    ranges: [AxisRange; N],
    /// Each axis's maximum velocity [rad/s]: the solutions' distance ([`travel_time`]).
    speed: [f64; N],
    tcp: Isometry3<f64>,
    tcp_inverse: Isometry3<f64>,
}

/// Why a TCP transform was refused ([`Kinematics::set_tcp`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TcpError {
    #[error("the TCP's {what} has {value}; it needs finite numbers")]
    NotFinite { what: &'static str, value: f64 },
    #[error("the TCP's orientation quaternion has norm {norm}; it needs a unit quaternion")]
    NotUnit { norm: f64 },
}

/// A pose as the protocol and the configuration write it (position [m], unit quaternion
/// `[x, y, z, w]`, as `mcm_shared::units::unit_quaternion` gives it) as an isometry. The
/// quaternion is taken as it is: [`Kinematics::set_tcp`] refuses one not of unit norm.
pub fn isometry(position: [f64; 3], orientation: [f64; 4]) -> Isometry3<f64> {
    let [x, y, z, w] = orientation;
    Isometry3::from_parts(
        Translation3::from(position),
        UnitQuaternion::new_unchecked(Quaternion::new(w, x, y, z)),
    )
}

/// The rotation of a quaternion as the protocol writes it, `[x, y, z, w]` (nalgebra's
/// constructor takes `w` first), normalised.
pub fn rotation(q: [f64; 4]) -> UnitQuaternion<f64> {
    let [x, y, z, w] = q;
    UnitQuaternion::new_normalize(Quaternion::new(w, x, y, z))
}

/// The transform of a tool's TCP ([`Tcp`]: its pose in the flange frame), for
/// [`Kinematics::set_tcp`].
pub fn tcp_transform(tcp: &Tcp) -> Isometry3<f64> {
    isometry(tcp.position, tcp.orientation)
}

impl Kinematics {
    /// The kinematics of the configured arm, with the TCP on the flange (the identity TCP
    /// transform; [`Kinematics::set_tcp`] sets the tool's).
    ///
    /// Refuses a configuration whose arm the analytic solver cannot handle
    /// ([`KinematicsError::Unsupported`], naming the link, the key and what is needed), and one
    /// with non-finite or out-of-range values. The axes' ranges are the reachable ones
    /// (`mcm_shared::ranges::reachable_deg`: the limits less `safety.limit_margin_deg`).
    pub fn from_config(cfg: &RobotConfig) -> Result<Kinematics, KinematicsError> {
        let arm = &cfg.arm;
        if arm.links.len() != N {
            return Err(KinematicsError::WrongCount {
                key: "arm.link",
                found: arm.links.len(),
            });
        }
        if cfg.axes.len() != N {
            return Err(KinematicsError::WrongCount {
                key: "axis",
                found: cfg.axes.len(),
            });
        }
        let invalid = |key: String, value: f64, allowed: &'static str| {
            Err(KinematicsError::Invalid {
                key,
                value,
                allowed,
            })
        };
        let mut links = [Dh::new(0.0, 0.0, 0.0, 0.0); N];
        for (i, (l, out)) in arm.links.iter().zip(links.iter_mut()).enumerate() {
            for (name, v) in [
                ("d", l.d),
                ("a", l.a),
                ("alpha_deg", l.alpha_deg),
                ("offset_deg", l.offset_deg),
            ] {
                if !v.is_finite() {
                    return invalid(format!("arm.link[{}].{name}", i + 1), v, "a finite value");
                }
            }
            *out = Dh::new(
                l.d,
                l.a,
                l.alpha_deg.to_radians(),
                l.offset_deg.to_radians(),
            );
        }
        let shape = Shape::new(&arm.links, &links)?;
        let mut ranges = [AxisRange { min: 0.0, max: 0.0 }; N];
        let mut speed = [0.0; N];
        for (i, a) in cfg.axes.iter().enumerate() {
            let (min, max) = reachable_deg(cfg, i);
            if !(min.is_finite() && max.is_finite() && min < max) {
                return invalid(
                    format!("axis[{}].min_deg", i + 1),
                    a.min_deg,
                    "finite limits, min_deg + safety.limit_margin_deg below \
                     max_deg - safety.limit_margin_deg",
                );
            }
            let v = a.max_velocity_deg_s;
            if !(v.is_finite() && v > 0.0) {
                return invalid(
                    format!("axis[{}].max_velocity_deg_s", i + 1),
                    v,
                    "a finite velocity > 0 deg/s",
                );
            }
            ranges[i] = AxisRange {
                min: min.to_radians(),
                max: max.to_radians(),
            };
            speed[i] = v.to_radians();
        }
        Ok(Kinematics {
            links,
            shape,
            ranges,
            speed,
            tcp: Isometry3::identity(),
            tcp_inverse: Isometry3::identity(),
        })
    }

    /// Set the TCP: its pose in the flange frame (the tool's `tcp` transform). Refused, the TCP
    /// unchanged, when not finite or its quaternion not of unit norm (within 1e-9).
    /// Allocation-free.
    pub fn set_tcp(&mut self, tcp: Isometry3<f64>) -> Result<(), TcpError> {
        let t = tcp.translation.vector;
        let q = tcp.rotation.quaternion().coords;
        for (what, v) in t
            .iter()
            .map(|v| ("position", v))
            .chain(q.iter().map(|v| ("orientation", v)))
        {
            if !v.is_finite() {
                return Err(TcpError::NotFinite { what, value: *v });
            }
        }
        let norm = q.norm();
        if (norm - 1.0).abs() > 1e-9 {
            return Err(TcpError::NotUnit { norm });
        }
        self.tcp = tcp;
        self.tcp_inverse = tcp.inverse();
        Ok(())
    }

    /// The TCP's pose in the flange frame.
    pub fn tcp(&self) -> Isometry3<f64> {
        self.tcp
    }

    /// Link `i` (0-based) as configured; `None` for i ≥ 6.
    pub fn link(&self, i: usize) -> Option<&Dh> {
        self.links.get(i)
    }

    /// The reachable range of each axis [rad], which every solution lies in.
    pub fn ranges(&self) -> &[AxisRange; N] {
        &self.ranges
    }

    /// Each axis's maximum velocity [rad/s], by which [`travel_time`] orders the solutions.
    pub fn max_velocities(&self) -> &[f64; N] {
        &self.speed
    }

    #[cfg(test)]
    pub(crate) fn set_ranges(&mut self, ranges: [AxisRange; N]) {
        self.ranges = ranges;
    }
}

#[cfg(test)]
mod tests;
