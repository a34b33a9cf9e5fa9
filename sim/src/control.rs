//! The simulator's control surface: fault injection ([`SimCommand`], the contract's `sim`
//! request, with 1-based typed axes) and ground truth ([`SimTruth`]) of the simulated robot,
//! implemented by [`crate::SimBus`].
//!
//! Runs inside the cycle: `apply` and `truth` never allocate, block or panic on bad input.
//! The real-time core reaches it only through its simulator edge, which the runner wires in
//! for `bus.backend = "sim"`.

pub use mcm_shared::command::SimCommand;

/// Ground truth of the simulated arm.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SimTruth {
    /// True joint angles [rad].
    pub position: [f64; 6],
    /// True joint velocities [rad/s].
    pub velocity: [f64; 6],
    /// The emergency switch is pressed.
    pub emergency_stop: bool,
}

/// Control surface of the simulated robot.
pub trait SimControl {
    /// Apply a fault injection. Errors name the bad argument.
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
