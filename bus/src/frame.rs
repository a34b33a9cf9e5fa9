//! A classic CAN frame with an 11-bit identifier: plain data, no I/O.
//!
//! Runs inside the cycle: `Copy`, no allocation.

use core::fmt;

/// A classic CAN 2.0A data frame (11-bit id, 0..=8 data bytes). Remote frames, extended ids
/// and CAN FD are not used by the MCM.
#[derive(Clone, Copy, PartialEq, Eq, Default)]
pub struct Frame {
    /// 11-bit identifier (COB-ID).
    pub id: u16,
    /// Number of valid bytes in `data` (0..=8).
    pub len: u8,
    /// Payload; bytes past `len` are zero.
    pub data: [u8; 8],
}

impl Frame {
    /// Largest 11-bit identifier.
    pub const MAX_ID: u16 = 0x7FF;

    /// A frame with the given id and payload. Returns `None` if the id has more than 11 bits
    /// or the payload more than 8 bytes.
    pub fn new(id: u16, payload: &[u8]) -> Option<Frame> {
        if id > Self::MAX_ID || payload.len() > 8 {
            return None;
        }
        let mut data = [0u8; 8];
        data[..payload.len()].copy_from_slice(payload);
        Some(Frame {
            id,
            len: payload.len() as u8,
            data,
        })
    }

    /// The valid payload bytes.
    pub fn payload(&self) -> &[u8] {
        &self.data[..usize::from(self.len.min(8))]
    }
}

/// candump spelling: `185#3702A0860100`.
impl fmt::Display for Frame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:03X}#", self.id)?;
        for b in self.payload() {
            write!(f, "{b:02X}")?;
        }
        Ok(())
    }
}

impl fmt::Debug for Frame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Frame({self})")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builds_and_prints_like_candump() {
        let f = Frame::new(0x185, &[0x37, 0x02, 0xA0, 0x86, 0x01, 0x00]).unwrap();
        assert_eq!(f.to_string(), "185#3702A0860100");
        assert_eq!(f.payload().len(), 6);
        assert_eq!(Frame::new(0x080, &[]).unwrap().to_string(), "080#");
    }

    #[test]
    fn refuses_bad_frames() {
        assert!(Frame::new(0x800, &[]).is_none());
        assert!(Frame::new(0x100, &[0; 9]).is_none());
    }
}
