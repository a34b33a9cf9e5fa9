//! The four PDOs of the MCM drive profile (`docs/drive-profile.md`, "Cyclic data"), packed and
//! unpacked little-endian.
//!
//! | PDO   | COB-ID  | bytes | content |
//! |-------|---------|-------|---------|
//! | RPDO1 | 0x200+n | 8 | controlword u16, target position i32 (counts), target torque i16 (‰ of 0x6076) |
//! | RPDO2 | 0x300+n | 5 | modes of operation i8, max current u16 (‰ of 0x6075), torque offset i16 (‰ of 0x6076) |
//! | TPDO1 | 0x180+n | 8 | statusword u16, position actual i32 (counts), current actual i16 (‰ of 0x6075) |
//! | TPDO2 | 0x280+n | 1 | modes of operation display i8 |
//!
//! Runs inside the cycle: no allocation; bad lengths are typed errors.
//!
//! ```
//! use mcm_rt_core::canopen::pdo::Rpdo1;
//! let f = Rpdo1 { controlword: 0x000F, target_position: 100_100, target_torque: 0 }.encode(5);
//! assert_eq!(f.to_string(), "205#0F00048701000000");
//! ```

use super::objects::{rpdo_id, tpdo_id};
use mcm_bus::Frame;
// The lengths the bus-load budget counts (`mcm_shared::busload`) are these PDOs' lengths.
use mcm_shared::busload::{CYCLIC_RPDO_BYTES, CYCLIC_TPDO_BYTES, RPDO2_BYTES};

/// A PDO frame had the wrong length.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error(
    "{pdo} from COB-ID 0x{id:03X} has {len} data bytes; the MCM drive profile maps exactly {expected}"
)]
pub struct PdoLengthError {
    pub pdo: &'static str,
    pub id: u16,
    pub len: u8,
    pub expected: u8,
}

fn check(frame: &Frame, pdo: &'static str, expected: u8) -> Result<(), PdoLengthError> {
    if frame.len == expected {
        Ok(())
    } else {
        Err(PdoLengthError {
            pdo,
            id: frame.id,
            len: frame.len,
            expected,
        })
    }
}

/// RPDO1: cyclic setpoints (transmission type 1, applied at the next SYNC).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Rpdo1 {
    pub controlword: u16,
    pub target_position: i32,
    pub target_torque: i16,
}

impl Rpdo1 {
    pub const LEN: u8 = CYCLIC_RPDO_BYTES;

    pub fn encode(&self, node: u8) -> Frame {
        let mut data = [0u8; 8];
        data[0..2].copy_from_slice(&self.controlword.to_le_bytes());
        data[2..6].copy_from_slice(&self.target_position.to_le_bytes());
        data[6..8].copy_from_slice(&self.target_torque.to_le_bytes());
        Frame {
            id: rpdo_id(1, node),
            len: Self::LEN,
            data,
        }
    }

    pub fn decode(frame: &Frame) -> Result<Rpdo1, PdoLengthError> {
        check(frame, "RPDO1", Self::LEN)?;
        let d = frame.data;
        Ok(Rpdo1 {
            controlword: u16::from_le_bytes([d[0], d[1]]),
            target_position: i32::from_le_bytes([d[2], d[3], d[4], d[5]]),
            target_torque: i16::from_le_bytes([d[6], d[7]]),
        })
    }
}

/// RPDO2: mode, current limit and the torque feed-forward of the position loop (0x60B2
/// torque offset: the gravity load in CSP, 0 in CST) (event-driven, applied on reception).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Rpdo2 {
    pub mode: i8,
    pub max_current_permille: u16,
    pub torque_offset: i16,
}

impl Rpdo2 {
    pub const LEN: u8 = RPDO2_BYTES;

    pub fn encode(&self, node: u8) -> Frame {
        let [c0, c1] = self.max_current_permille.to_le_bytes();
        let [t0, t1] = self.torque_offset.to_le_bytes();
        Frame {
            id: rpdo_id(2, node),
            len: Self::LEN,
            data: [self.mode as u8, c0, c1, t0, t1, 0, 0, 0],
        }
    }

    pub fn decode(frame: &Frame) -> Result<Rpdo2, PdoLengthError> {
        check(frame, "RPDO2", Self::LEN)?;
        let d = frame.data;
        Ok(Rpdo2 {
            mode: d[0] as i8,
            max_current_permille: u16::from_le_bytes([d[1], d[2]]),
            torque_offset: i16::from_le_bytes([d[3], d[4]]),
        })
    }
}

/// TPDO1: cyclic feedback, sampled at SYNC.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Tpdo1 {
    pub statusword: u16,
    pub position: i32,
    pub current_permille: i16,
}

impl Tpdo1 {
    pub const LEN: u8 = CYCLIC_TPDO_BYTES;

    pub fn encode(&self, node: u8) -> Frame {
        let mut data = [0u8; 8];
        data[0..2].copy_from_slice(&self.statusword.to_le_bytes());
        data[2..6].copy_from_slice(&self.position.to_le_bytes());
        data[6..8].copy_from_slice(&self.current_permille.to_le_bytes());
        Frame {
            id: tpdo_id(1, node),
            len: Self::LEN,
            data,
        }
    }

    pub fn decode(frame: &Frame) -> Result<Tpdo1, PdoLengthError> {
        check(frame, "TPDO1", Self::LEN)?;
        let d = frame.data;
        Ok(Tpdo1 {
            statusword: u16::from_le_bytes([d[0], d[1]]),
            position: i32::from_le_bytes([d[2], d[3], d[4], d[5]]),
            current_permille: i16::from_le_bytes([d[6], d[7]]),
        })
    }
}

/// TPDO2: modes of operation display (sent on change and on entering OPERATIONAL).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Tpdo2 {
    pub mode_display: i8,
}

impl Tpdo2 {
    pub const LEN: u8 = 1;

    pub fn encode(&self, node: u8) -> Frame {
        Frame {
            id: tpdo_id(2, node),
            len: Self::LEN,
            data: [self.mode_display as u8, 0, 0, 0, 0, 0, 0, 0],
        }
    }

    pub fn decode(frame: &Frame) -> Result<Tpdo2, PdoLengthError> {
        check(frame, "TPDO2", Self::LEN)?;
        Ok(Tpdo2 {
            mode_display: frame.data[0] as i8,
        })
    }
}

#[cfg(test)]
mod tests;
