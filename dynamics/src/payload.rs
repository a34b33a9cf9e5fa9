//! The payload's mass and centre of mass from holding torques: least squares over poses.
//!
//! The gravity torque of a point load is linear in θ = (m, m·cx, m·cy, m·cz), the centre of
//! mass c in the flange frame (DH frame 6): at each pose q, the torque the drives hold with
//! minus the model's gravity torque without the load is `Y(q)·θ`. `Y`'s columns come from the
//! model itself ([`regressor`]): the gravity torques of a unit mass at the flange's origin and
//! at unit offsets along the flange's axes, less those of the arm without a load, so there is
//! no second copy of the dynamics. The load's own inertia does not enter gravity and is not
//! estimated.
//!
//! [`PayloadEstimator`] accumulates the 4×4 normal system `YᵀY θ = Yᵀr` pose by pose (six rows,
//! one per axis) and solves it once the poses are in ([`PayloadEstimator::estimate`]); it
//! refuses poses that do not excite every unknown ([`PayloadError::IllConditioned`]: the
//! condition number of `Y` with its columns scaled to unit length above
//! [`MAX_CONDITION`]), which [`PayloadEstimator::condition`] tells before anything is measured.
//! The `residual` it reports is the root mean square, over every axis at every pose, of the
//! measured torque less the torque the estimate explains [N·m]: the part of the measurements
//! the model of a point load does not account for (friction the averaging left, noise, an
//! error of the arm's own model).
//!
//! Runs inside the cycle: plain `Copy` data, fixed-size nalgebra types, no allocation, no
//! panic for any input (a non-finite input makes the estimate [`PayloadError::NotFinite`]).
//!
//! ```
//! use mcm_dynamics::{ArmModel, PayloadEstimator};
//! use mcm_shared::tool::{Tcp, Tool};
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let model = ArmModel::from_config(&cfg);
//! let mut truth = model.clone();
//! truth.set_tool(&Tool::new(Tcp::FLANGE, 2.0, [0.01, 0.0, 0.06], None).unwrap());
//! let mut est = PayloadEstimator::new();
//! for q in [[0.0, 0.3, 0.4, 0.0, 0.5, 0.0], [0.0, -0.3, 0.2, 1.5, -0.6, 0.0], [0.0, 0.1, -0.5, -1.0, 1.0, 1.5]] {
//!     est.add(&model, &q, &truth.gravity_torques(&q));
//! }
//! let p = est.estimate().unwrap();
//! assert!((p.mass - 2.0).abs() < 1e-9);
//! assert!((p.center_of_mass[2] - 0.06).abs() < 1e-9);
//! ```

use super::ArmModel;
use mcm_shared::NUM_AXES;
use mcm_shared::tool::Tool;
use nalgebra::{Matrix4, SMatrix, SVector, Vector4};

const N: usize = NUM_AXES;

/// The regressor of one pose: the gravity torque per unit of each unknown (columns m, m·cx,
/// m·cy, m·cz) [N·m/kg, N·m/(kg·m)].
type Regressor = SMatrix<f64, N, 4>;

/// The largest condition number of the column-scaled regressor an estimate is made with: the
/// relative error of the estimate is at most this many times that of the torques (the
/// procedure's poses have at most 5.8 from starts across the reach; bending the elbow by only
/// a degree takes it above this).
pub const MAX_CONDITION: f64 = 15.0;

/// Below this mass [kg] the centre of mass is not reported (a first moment divided by almost
/// nothing is noise): an estimate of no load.
pub const MIN_MASS_FOR_CENTER_KG: f64 = 0.05;

/// Why no estimate.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum PayloadError {
    /// The poses do not excite every unknown: `condition` is the column-scaled regressor's
    /// condition number.
    #[error(
        "the poses do not tell the payload's mass and centre of mass apart (condition number {condition:.3e}; expected at most {limit})"
    )]
    IllConditioned { condition: f64, limit: f64 },
    /// A pose or a torque given was not finite.
    #[error("a pose or a measured torque is not a finite number")]
    NotFinite,
}

/// What the poses say about the load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PayloadEstimate {
    /// [kg]; never negative (a negative estimate is noise around no load: 0).
    pub mass: f64,
    /// Flange frame [m]; zeros when `mass` is below [`MIN_MASS_FOR_CENTER_KG`].
    pub center_of_mass: [f64; 3],
    /// RMS of the torque the estimate does not explain, over every axis and pose [N·m].
    pub residual_nm: f64,
}

/// The regressor at `q` and the gravity torque of the arm without a load (the model's
/// links, its tool's mass taken off) [N·m].
fn regressor(model: &ArmModel, q: &[f64; N]) -> (Regressor, [f64; N]) {
    let mut scratch = model.clone();
    let tool = *model.tool();
    let at = |scratch: &mut ArmModel, mass: f64, c: [f64; 3]| {
        scratch.set_tool(&Tool {
            mass,
            center_of_mass: c,
            inertia: [0.0; 6],
            ..tool
        });
        SVector::<f64, N>::from(scratch.gravity_torques(q))
    };
    let bare = at(&mut scratch, 0.0, [0.0; 3]);
    let origin = at(&mut scratch, 1.0, [0.0; 3]);
    let mut y = Regressor::zeros();
    y.set_column(0, &(origin - bare));
    for k in 0..3 {
        let mut c = [0.0; 3];
        c[k] = 1.0;
        y.set_column(k + 1, &(at(&mut scratch, 1.0, c) - origin));
    }
    (y, bare.into())
}

/// The normal system of the poses added so far.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PayloadEstimator {
    /// `YᵀY`.
    normal: Matrix4<f64>,
    /// `Yᵀr`.
    rhs: Vector4<f64>,
    /// `rᵀr`.
    sum_sq: f64,
    rows: u32,
    finite: bool,
}

impl Default for PayloadEstimator {
    fn default() -> Self {
        Self::new()
    }
}

impl PayloadEstimator {
    pub const fn new() -> PayloadEstimator {
        PayloadEstimator {
            normal: Matrix4::new(
                0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
            ),
            rhs: Vector4::new(0.0, 0.0, 0.0, 0.0),
            sum_sq: 0.0,
            rows: 0,
            finite: true,
        }
    }

    /// One pose: the arm at rest at `q` [rad] holding with `measured` joint torques [N·m];
    /// `model` is the arm's (its tool's load is taken off: the torques are explained by the
    /// links and the unknown load).
    pub fn add(&mut self, model: &ArmModel, q: &[f64; N], measured: &[f64; N]) {
        let (y, bare) = regressor(model, q);
        let r = SVector::<f64, N>::from(*measured) - SVector::<f64, N>::from(bare);
        self.add_rows(&y, &r);
    }

    /// A pose's regressor alone, to judge the poses before measuring
    /// ([`PayloadEstimator::condition`]).
    pub fn add_pose(&mut self, model: &ArmModel, q: &[f64; N]) {
        let (y, _) = regressor(model, q);
        self.add_rows(&y, &SVector::<f64, N>::zeros());
    }

    fn add_rows(&mut self, y: &Regressor, r: &SVector<f64, N>) {
        self.finite &= y.iter().chain(r.iter()).all(|v| v.is_finite());
        self.normal += y.transpose() * y;
        self.rhs += y.transpose() * r;
        self.sum_sq += r.norm_squared();
        self.rows += N as u32;
    }

    /// The condition number of the column-scaled regressor of the poses so far (infinite
    /// when an unknown is not excited at all).
    pub fn condition(&self) -> f64 {
        let d = self.normal.diagonal();
        if !self.finite || d.iter().any(|v| v.is_nan() || *v <= 0.0) {
            return f64::INFINITY;
        }
        let s = d.map(|v| 1.0 / v.sqrt());
        let scaled = Matrix4::from_fn(|i, j| self.normal[(i, j)] * s[i] * s[j]);
        let eig = scaled.symmetric_eigen().eigenvalues;
        let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| {
            (lo.min(*v), hi.max(*v))
        });
        if lo > 0.0 && hi.is_finite() {
            (hi / lo).sqrt()
        } else {
            f64::INFINITY
        }
    }

    /// Whether the poses so far tell every unknown apart: `Err` with the condition number
    /// when it is above [`MAX_CONDITION`].
    pub fn judge(&self) -> Result<(), PayloadError> {
        let condition = self.condition();
        if condition.is_nan() || condition > MAX_CONDITION {
            return Err(PayloadError::IllConditioned {
                condition,
                limit: MAX_CONDITION,
            });
        }
        Ok(())
    }

    /// The least-squares estimate of the poses added.
    pub fn estimate(&self) -> Result<PayloadEstimate, PayloadError> {
        if !self.finite {
            return Err(PayloadError::NotFinite);
        }
        self.judge()?;
        let ill = PayloadError::IllConditioned {
            condition: f64::INFINITY,
            limit: MAX_CONDITION,
        };
        let theta = self.normal.cholesky().ok_or(ill)?.solve(&self.rhs);
        // |r − Yθ|² = rᵀr − 2θᵀYᵀr + θᵀYᵀYθ (rounding may take it a little below 0).
        let unexplained =
            self.sum_sq - 2.0 * theta.dot(&self.rhs) + theta.dot(&(self.normal * theta));
        let residual_nm = (unexplained.max(0.0) / f64::from(self.rows.max(1))).sqrt();
        let mass = theta[0];
        let center_of_mass = if mass >= MIN_MASS_FOR_CENTER_KG {
            [theta[1] / mass, theta[2] / mass, theta[3] / mass]
        } else {
            [0.0; 3]
        };
        Ok(PayloadEstimate {
            mass: mass.max(0.0),
            center_of_mass,
            residual_nm,
        })
    }
}

#[cfg(test)]
mod tests;
