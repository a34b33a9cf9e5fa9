//! The CANopen master of the MCM real-time core, sans-I/O: it consumes received frames and
//! produces frames to send, with time passed in by the caller, so the same code runs against
//! the simulated drives and against real drives through SocketCAN.
//!
//! It implements exactly the subset the MCM drive profile needs (see
//! `docs/drive-profile.md`):
//!
//! - [`objects`]: object indices and COB-ID helpers;
//! - [`nmt`]: NMT commands, SYNC, heartbeat / boot-up frames;
//! - [`sdo`]: expedited SDO client with typed abort codes;
//! - [`pdo`]: RPDO1/RPDO2/TPDO1/TPDO2 of the profile;
//! - [`emcy`]: EMCY decoding into a readable error;
//! - [`heartbeat`]: heartbeat consumer per drive, producer for the master;
//! - [`cia402`]: controlword / statusword, state decoding, transition table;
//! - [`boot`]: the per-node configuration sequence;
//! - [`busload`]: worst-case bus load check at start-up;
//! - [`master`]: the [`Master`] that ties it together, with its interface types in [`types`].
//!
//! Everything except `busload` and `Master::new` runs inside the cycle and allocates nothing.

pub mod boot;
/// The worst-case bus load (in the contract: the gateway shows it too).
pub use mcm_shared::busload;
pub mod cia402;
pub mod emcy;
pub mod heartbeat;
pub mod master;
pub mod nmt;
pub mod objects;
pub mod pdo;
pub mod sdo;
pub mod types;

#[cfg(test)]
mod testdrive;

pub use master::{
    AxisFeedback, DriveRequest, FrameBuf, LostReason, Master, MasterEvent, MasterSetupError,
};
