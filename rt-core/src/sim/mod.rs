//! The simulated P-Rob2: six simulated CiA 402 servo drives on a simulated CAN bus, moving the
//! arm model of [`crate::dynamics`]. Selected by `bus.backend = "sim"`; the CANopen master
//! drives it through the same [`crate::bus::Bus`] trait as real drives, frame for frame as
//! `DRIVE_PROFILE.md` specifies.
//!
//! Runs inside the cycle: after construction nothing allocates, blocks or panics on bad input.
//!
//! Structure:
//! - [`bus::SimBus`]: the bus (implements [`crate::bus::Bus`] and [`crate::bus::SimControl`]);
//!   lock-step time: time advances only on SYNC, by one cycle period; fault injection;
//! - [`drive::SimDrive`]: one drive = object dictionary ([`od`]), expedited SDO server
//!   ([`sdo_server`]), NMT slave with heartbeats ([`nmt`]), PDO engine ([`pdo`]), CiA 402 state
//!   machine ([`cia402`]), position controller ([`servo`]), current limit, encoder model.
//!
//! ```
//! use mcm_rt_core::bus::{Bus, Frame};
//! use mcm_rt_core::sim::SimBus;
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let mut bus = SimBus::new(&cfg);
//! // the six drives have booted: 701#00 .. 706#00
//! assert_eq!(bus.recv(0).unwrap().unwrap().to_string(), "701#00");
//! bus.send(&Frame::new(0x080, &[]).unwrap()).unwrap(); // SYNC: 5 ms pass
//! assert_eq!(bus.now_ns(), 5_000_000);
//! ```

mod abort;
pub mod bus;
pub mod cia402;
pub mod drive;
pub mod nmt;
pub mod od;
pub mod pdo;
pub mod sdo_server;
pub mod servo;

#[cfg(test)]
mod bus_tests;
#[cfg(test)]
mod test_master;

pub use abort::SdoAbort;
pub use bus::SimBus;
pub use drive::SimDrive;

use crate::bus::Frame;

/// Where a simulated node puts the frames it transmits.
pub trait FrameSink {
    /// Transmit one frame.
    fn emit(&mut self, frame: Frame);
}

/// A sink that drops every frame: the cable of a disconnected drive.
#[derive(Debug, Clone, Copy, Default)]
pub struct Discard;

impl FrameSink for Discard {
    fn emit(&mut self, _frame: Frame) {}
}

#[cfg(test)]
impl FrameSink for Vec<Frame> {
    fn emit(&mut self, frame: Frame) {
        self.push(frame);
    }
}
