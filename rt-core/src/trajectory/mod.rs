//! # Trajectory maths of the real-time core
//!
//! Pure functions over plain data: every type here is `Copy` (except the PVT ring, which is a
//! fixed-size array), nothing allocates, nothing panics on bad input (typed errors instead).
//! Planning runs once per command and is O(1) per axis; sampling is O(1) per cycle, so both
//! may run **inside the cycle**.
//!
//! Units are SI throughout: rad, rad/s, rad/s², rad/s³, s. Degrees belong to the protocol layer.
//!
//! | module | what |
//! |---|---|
//! | [`profile`] | 1-D rest-to-rest profile: trapezoid (no jerk limit) or double-S (7 phases) |
//! | [`sync`] | `move_all` from rest: phase-synchronised straight line in joint space |
//! | [`online`] | re-planning one axis from any (p, v, a); six independent axis plans |
//! | [`segments`] | an axis plan as constant-jerk segments; its closed-form range and peaks |
//! | [`hermite`] | cubic Hermite PVT segments and their closed-form limit checks |
//! | [`pvt_queue`] | fixed-capacity ring of PVT points with atomic batch push |
//! | [`controlled_stop`] | controlled stop from a moving state; stopping distances d₂, d₃ |
//!
//! ```
//! use mcm_rt_core::trajectory::{AxisLimits, MovePlan, PlanError};
//! let lim = AxisLimits { velocity: 1.5, acceleration: 3.0, jerk: Some(30.0) };
//! let plan = MovePlan::plan([0.0; 6], [1.0, 0.5, 0.0, 0.0, 0.0, -0.2], &[lim; 6], 0.5)?;
//! let s = plan.sample(plan.duration() / 2.0); // every cycle: t since the command was accepted
//! assert!(s.velocity[0] > 0.0);
//! assert_eq!(plan.sample(plan.duration()).position[0], 1.0);
//! # Ok::<(), PlanError>(())
//! ```

pub mod controlled_stop;
pub mod error;
pub mod hermite;
pub mod online;
pub mod profile;
pub mod pvt_queue;
pub mod segments;
pub mod sync;

pub use controlled_stop::{StopPlan, stopping_distance, stopping_distance_from};
pub use error::{PlanError, PvtSegmentError, QueueFull, SegmentError, StopError};
pub use hermite::{Hermite, PvtSegment};
pub use online::{JointPlan, plan_from_state};
pub use profile::Profile1D;
pub use pvt_queue::{DEFAULT_PVT_CAPACITY, PvtPoint, PvtQueue};
pub use segments::AxisPlan;
pub use sync::MovePlan;

use mcm_shared::NUM_AXES;

/// Kinematic limits of one axis (rad/s, rad/s², rad/s³). `jerk: None` means no jerk limit
/// (acceleration may jump), which selects trapezoidal profiles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisLimits {
    pub velocity: f64,
    pub acceleration: f64,
    pub jerk: Option<f64>,
}

impl AxisLimits {
    /// The limits scaled by a velocity factor `f`: V = f·v_max, A = f·a_max, J = f·j_max (the
    /// factor scales each axis's maximum velocity, acceleration and jerk: docs/protocol.md,
    /// "move_axis, move_all"). Not validated here.
    pub fn scaled(self, f: f64) -> AxisLimits {
        AxisLimits {
            velocity: f * self.velocity,
            acceleration: f * self.acceleration,
            jerk: self.jerk.map(|j| f * j),
        }
    }

    /// Checks that every limit is finite and > 0.
    pub fn validate(&self) -> Result<(), PlanError> {
        let ok = |x: f64| x.is_finite() && x > 0.0;
        if !ok(self.velocity) {
            return Err(PlanError::Limit {
                name: "velocity",
                value: self.velocity,
            });
        }
        if !ok(self.acceleration) {
            return Err(PlanError::Limit {
                name: "acceleration",
                value: self.acceleration,
            });
        }
        if let Some(j) = self.jerk
            && !ok(j)
        {
            return Err(PlanError::Limit {
                name: "jerk",
                value: j,
            });
        }
        Ok(())
    }
}

/// Commanded joint state at one instant (rad, rad/s, rad/s²).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JointSample {
    pub position: [f64; NUM_AXES],
    pub velocity: [f64; NUM_AXES],
    pub acceleration: [f64; NUM_AXES],
}
