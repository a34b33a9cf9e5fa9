//! How near a configuration is to the arm's singularities, where a Cartesian direction needs
//! unbounded joint velocities:
//!
//! - **wrist**: axes 4 and 6 aligned (θ5 = 0 or 180°); measured by the angle between them;
//! - **elbow**: the arm stretched or folded (the forearm in line with the upper arm); measured
//!   by the angle between the forearm line and the upper arm's line;
//! - **shoulder**: the wrist centre on axis 1 (beside it by the shoulder offset, when the arm
//!   has one); measured by the wrist centre's distance from there.
//!
//! [`SingularityMargins::DEFAULT`] says what counts as near.

use crate::{Kinematics, N};

/// The measures of [`Kinematics::singularities`]: 0 at the singularity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Singularities {
    /// Angle between axes 4 and 6, 0..=π/2 [rad].
    pub wrist_rad: f64,
    /// Angle between the forearm line and the upper arm's line, 0..=π/2 [rad].
    pub elbow_rad: f64,
    /// Distance of the wrist centre from where axis 1 no longer decides it [m].
    pub shoulder_m: f64,
}

/// Below which measure a configuration is near a singularity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SingularityMargins {
    pub wrist_rad: f64,
    pub elbow_rad: f64,
    pub shoulder_m: f64,
}

impl SingularityMargins {
    /// 5° at the wrist and the elbow, 5 cm at the shoulder. At the wrist and elbow margins a
    /// Cartesian velocity needs about 1/sin 5° ≈ 11.5 times the joint velocity it needs far
    /// from them; at the shoulder margin, 1 cm/s sideways at the wrist centre takes 0.2 rad/s
    /// of axis 1.
    pub const DEFAULT: SingularityMargins = SingularityMargins {
        wrist_rad: 5.0 * std::f64::consts::PI / 180.0,
        elbow_rad: 5.0 * std::f64::consts::PI / 180.0,
        shoulder_m: 0.05,
    };
}

impl Default for SingularityMargins {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Which singularities a configuration is near.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Near {
    pub wrist: bool,
    pub elbow: bool,
    pub shoulder: bool,
}

impl Near {
    /// Near any of them.
    pub fn any(&self) -> bool {
        self.wrist || self.elbow || self.shoulder
    }
}

impl Singularities {
    /// Which measures are below their margins.
    pub fn near(&self, margins: &SingularityMargins) -> Near {
        Near {
            wrist: self.wrist_rad < margins.wrist_rad,
            elbow: self.elbow_rad < margins.elbow_rad,
            shoulder: self.shoulder_m < margins.shoulder_m,
        }
    }
}

impl Kinematics {
    /// How near the configuration `q` [rad] is to each singularity. Allocation-free.
    pub fn singularities(&self, q: &[f64; N]) -> Singularities {
        let f = self.frames(q);
        let wrist = f.axis(3).cross(&f.axis(5)).norm().min(1.0).asin();
        let phi = q[2] + self.links[2].offset + self.shape.forearm_angle;
        let elbow = phi.sin().abs().min(1.0).asin();
        // The wrist centre is the origin of frame 4.
        let c = f.origin[3];
        let e = self.shape.lateral;
        let shoulder = (c.x * c.x + c.y * c.y - e * e).max(0.0).sqrt();
        Singularities {
            wrist_rad: wrist,
            elbow_rad: elbow,
            shoulder_m: shoulder,
        }
    }
}

#[cfg(test)]
mod tests;
