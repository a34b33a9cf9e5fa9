//! The drive bus: a small abstraction over "send a frame, receive frames", with two backends
//! chosen by the configuration (`bus.backend`): `socketcan` for real drives and `sim` for the
//! simulated P-Rob2. The CANopen master above it is the same code for both.
//!
//! Runs inside the cycle: `send` and `recv` never block past their deadline and never allocate.

mod frame;

#[cfg(unix)]
pub mod candump;
#[cfg(target_os = "linux")]
pub mod socketcan;

pub use frame::Frame;

/// A bus operation failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum BusError {
    /// The transmit queue is full; the frame was not sent.
    #[error("CAN transmit queue of {interface} is full; frame {frame} not sent")]
    TxQueueFull {
        interface: &'static str,
        frame: Frame,
    },
    /// The interface reported an error (errno).
    #[error("CAN interface {interface} failed: os error {errno}")]
    Os { interface: &'static str, errno: i32 },
    /// The controller is bus-off.
    #[error("CAN interface {interface} is bus-off")]
    BusOff { interface: &'static str },
}

/// Send frames, receive frames. Implemented by the SocketCAN backend and the simulated bus.
pub trait Bus {
    /// Queue one frame for transmission. Never blocks.
    fn send(&mut self, frame: &Frame) -> Result<(), BusError>;

    /// The next received frame, waiting at most until `deadline_ns` (`CLOCK_MONOTONIC`);
    /// `Ok(None)` when none arrived by then. A deadline in the past polls.
    fn recv(&mut self, deadline_ns: u64) -> Result<Option<Frame>, BusError>;

    /// The simulation's control surface, when this bus is the simulated robot.
    fn sim(&mut self) -> Option<&mut dyn SimControl> {
        None
    }
}

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

/// Control surface of the simulated robot, reached through [`Bus::sim`].
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
