//! # mcm-bus: the drive bus of the Motion Control Module
//!
//! A small abstraction over "send a frame, receive frames", with two backends chosen by the
//! configuration (`bus.backend`): `socketcan` for real drives ([`socketcan`]) and `sim` for
//! the simulated P-Rob2 (the `mcm-sim` crate). The CANopen master above it is the same code for
//! both. [`candump::LoggingBus`] records the frames of any bus in candump format.
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
}
