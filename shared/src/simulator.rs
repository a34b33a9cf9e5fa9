//! The simulated robot's control surface, as the real-time core reaches it: fault injection
//! ([`crate::command::SimCommand`], the contract's `sim` request) and ground truth
//! ([`SimTruth`]), behind [`SimControl`]. `mcm-sim`'s simulated bus implements it; the core's
//! simulator edge calls it and publishes the truth, whether or not the simulator is built in.
//!
//! Runs inside the cycle: `apply` and `truth` must not allocate, block or panic on bad input.
//!
//! ```
//! use mcm_shared::command::Axis;
//! use mcm_shared::reply::Reason;
//! use mcm_shared::simulator::SimCommandError;
//! let e = SimCommandError::TorqueNotFinite { index: 2, value: f64::NAN };
//! assert_eq!(e.to_string(), "sim: external_torques[2] = NaN is not finite");
//! let Reason::OutOfRange { axis, .. } = Reason::from(e) else { panic!() };
//! assert_eq!(axis, Axis::from_index(2));
//! ```

use crate::NUM_AXES;
use crate::command::{Axis, SimCommand};
use crate::reply::Reason;

/// Ground truth of the simulated arm, as the state publishes it (`sim_true_position`,
/// `sim_true_velocity`, `STATE_SIM_ESTOP`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SimTruth {
    /// True joint angles [rad].
    pub position: [f64; NUM_AXES],
    /// True joint velocities [rad/s].
    pub velocity: [f64; NUM_AXES],
    /// The simulated emergency switch is pressed.
    pub emergency_stop: bool,
}

/// Control surface of the simulated robot.
pub trait SimControl {
    /// Apply a fault injection; a refused one changes nothing. Errors name the bad argument.
    fn apply(&mut self, cmd: &SimCommand) -> Result<(), SimCommandError>;
    /// The true state of the simulated arm.
    fn truth(&self) -> SimTruth;
}

/// A `sim` command argument was refused (axes are typed, so only a value built without the
/// contract's decoder can be refused).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimCommandError {
    #[error("sim: external_torques[{index}] = {value} is not finite")]
    TorqueNotFinite { index: usize, value: f64 },
}

/// A refused `sim` command as its reply says it: `out_of_range`, naming the axis and the value.
impl From<SimCommandError> for Reason {
    fn from(e: SimCommandError) -> Reason {
        match e {
            SimCommandError::TorqueNotFinite { index, value } => Reason::OutOfRange {
                axis: Axis::from_index(index),
                value,
                min: f64::MIN,
                max: f64::MAX,
            },
        }
    }
}
