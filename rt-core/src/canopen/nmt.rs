//! NMT node control, SYNC and the NMT state byte of heartbeat / boot-up frames (CiA 301).
//!
//! Runs inside the cycle: pure frame encoders and decoders, no allocation.
//!
//! ```
//! use mcm_rt_core::canopen::nmt::{nmt_frame, NmtCommand};
//! assert_eq!(nmt_frame(NmtCommand::ResetCommunication, 5).to_string(), "000#8205");
//! ```

use super::objects::{NMT_ID, SYNC_ID, heartbeat_id};
use mcm_bus::Frame;

/// NMT command specifiers (`000#<cs><node>`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum NmtCommand {
    /// -> OPERATIONAL.
    Start = 0x01,
    /// -> STOPPED.
    Stop = 0x02,
    /// -> PRE-OPERATIONAL.
    EnterPreOperational = 0x80,
    /// Application + communication reset, then boot-up.
    ResetNode = 0x81,
    /// Communication reset, then boot-up.
    ResetCommunication = 0x82,
}

/// NMT state reported in heartbeat frames (`700+n#<state>`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NmtState {
    /// `00`: the boot-up message.
    BootUp,
    /// `04`.
    Stopped,
    /// `05`.
    Operational,
    /// `7F`.
    PreOperational,
    /// Any other byte (malformed or vendor-specific).
    Unknown(u8),
}

impl NmtState {
    pub const fn from_byte(b: u8) -> NmtState {
        match b & 0x7F {
            0x00 => NmtState::BootUp,
            0x04 => NmtState::Stopped,
            0x05 => NmtState::Operational,
            0x7F => NmtState::PreOperational,
            _ => NmtState::Unknown(b),
        }
    }

    pub const fn to_byte(self) -> u8 {
        match self {
            NmtState::BootUp => 0x00,
            NmtState::Stopped => 0x04,
            NmtState::Operational => 0x05,
            NmtState::PreOperational => 0x7F,
            NmtState::Unknown(b) => b,
        }
    }

    pub const fn name(self) -> &'static str {
        match self {
            NmtState::BootUp => "boot-up",
            NmtState::Stopped => "STOPPED",
            NmtState::Operational => "OPERATIONAL",
            NmtState::PreOperational => "PRE-OPERATIONAL",
            NmtState::Unknown(_) => "unknown NMT state",
        }
    }
}

/// `000#<cs><node>`; node 0 addresses all nodes.
pub fn nmt_frame(cmd: NmtCommand, node: u8) -> Frame {
    Frame {
        id: NMT_ID,
        len: 2,
        data: [cmd as u8, node, 0, 0, 0, 0, 0, 0],
    }
}

/// `080#` (DLC 0, no counter).
pub const fn sync_frame() -> Frame {
    Frame {
        id: SYNC_ID,
        len: 0,
        data: [0; 8],
    }
}

/// `700+n#<state>`.
pub fn heartbeat_frame(node: u8, state: NmtState) -> Frame {
    Frame {
        id: heartbeat_id(node),
        len: 1,
        data: [state.to_byte(), 0, 0, 0, 0, 0, 0, 0],
    }
}

/// The state byte of a heartbeat / boot-up frame, if `frame` has exactly one data byte.
pub fn decode_heartbeat(frame: &Frame) -> Option<NmtState> {
    (frame.len == 1).then(|| NmtState::from_byte(frame.data[0]))
}

#[cfg(test)]
mod tests;
