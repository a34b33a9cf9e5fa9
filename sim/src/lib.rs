//! # mcm-sim: the simulated P-Rob2
//!
//! Six simulated CiA 402 servo drives on a simulated CAN bus, moving the arm model of
//! `mcm-dynamics` ([`physics`]). Selected by `bus.backend = "sim"`; the CANopen master drives it
//! through the same [`mcm_bus::Bus`] trait as real drives, frame for frame as
//! `docs/drive-profile.md` specifies. Fault injection and ground truth go through [`SimControl`]
//! (`mcm_shared::simulator`, the one control surface), which only the real-time core's
//! simulator edge uses; [`snapshot`] keeps the simulated robot across a restart of `mcm-rt`.
//!
//! Runs inside the cycle: after construction nothing allocates, blocks or panics on bad input
//! (except [`snapshot`] and [`SimBus::save`]/[`SimBus::resume`], which do file I/O outside it).
//!
//! Structure:
//! - [`bus::SimBus`]: the bus (implements [`mcm_bus::Bus`] and [`SimControl`]);
//!   lock-step time: time advances only on SYNC, by one cycle period; fault injection;
//! - [`drive::SimDrive`]: one drive = object dictionary ([`od`]), expedited SDO server
//!   ([`sdo_server`]), NMT slave with heartbeats ([`nmt`]), PDO engine ([`pdo`]), CiA 402 state
//!   machine ([`cia402`]), position controller ([`servo`]), current limit, encoder model.
//!
//! ```
//! use mcm_bus::{Bus, Frame};
//! use mcm_sim::SimBus;
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
pub mod physics;
pub mod sdo_server;
pub mod servo;
pub mod snapshot;

#[cfg(test)]
mod test_master;

pub use abort::SdoAbort;
pub use bus::SimBus;
pub use drive::SimDrive;
pub use mcm_shared::command::SimCommand;
pub use mcm_shared::simulator::{SimCommandError, SimControl, SimTruth};
pub use physics::{ArmSim, BRAKE_HOLD_FACTOR, MAX_JOINT_SPEED_RAD_S};

use mcm_bus::Frame;

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
