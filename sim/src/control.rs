//! The simulator's control surface: fault injection ([`SimCommand`]) and ground truth
//! ([`SimTruth`]) of the simulated robot, implemented by [`crate::SimBus`].
//!
//! Runs inside the cycle: `apply` and `truth` never allocate, block or panic on bad input.
//! The real-time core reaches it only through its simulator edge, which the runner wires in
//! for `bus.backend = "sim"`.

/// A fault to inject into the simulated robot (the `sim` command). Fields left `None`/`false`
/// change nothing. Axes are 0-based here (0..6).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SimCommand {
    pub emergency_stop: Option<bool>,
    pub disconnect_axis: Option<usize>,
    pub reconnect_axis: Option<usize>,
    pub block_axis: Option<usize>,
    pub unblock_axis: Option<usize>,
    /// Joint-side torques of a hand pushing on the joints [Nm], until set back to zeros.
    pub external_torques: Option<[f64; 6]>,
    pub power_cycle: bool,
}

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

/// A `sim` command argument was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimCommandError {
    #[error("sim: {argument} = {value} is not an axis; allowed 1..=6")]
    NoSuchAxis {
        argument: &'static str,
        value: usize,
    },
    #[error("sim: external_torques[{index}] = {value} is not finite")]
    TorqueNotFinite { index: usize, value: f64 },
}
