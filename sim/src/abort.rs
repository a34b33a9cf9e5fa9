//! SDO abort reasons of the simulated drive: a typed error per CiA 301 abort code.
//!
//! Runs inside the cycle: plain `Copy` data, no allocation. Every refused object access in
//! the simulated drive ends in one of these; [`SdoAbort::code`] gives the 32-bit code that
//! goes on the wire (bytes 4..7 of the `0x80` abort response).
//!
//! ```
//! use mcm_sim::SdoAbort;
//! let a = SdoAbort::WriteToReadOnly { index: 0x6041, sub: 0 };
//! assert_eq!(a.code(), 0x0601_0002);
//! ```

/// Why the simulated drive refused an SDO request.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum SdoAbort {
    #[error("object 0x{index:04X} does not exist in the drive's object dictionary")]
    ObjectDoesNotExist { index: u16 },
    #[error("sub-index 0x{index:04X}:{sub} does not exist")]
    SubIndexDoesNotExist { index: u16, sub: u8 },
    #[error("object 0x{index:04X}:{sub} is read-only; only reads are allowed")]
    WriteToReadOnly { index: u16, sub: u8 },
    #[error("object 0x{index:04X}:{sub} is write-only; only writes are allowed")]
    ReadOfWriteOnly { index: u16, sub: u8 },
    #[error("object 0x{index:04X}:{sub} has {expected} bytes, the request gave {given}")]
    LengthMismatch {
        index: u16,
        sub: u8,
        expected: u8,
        given: u8,
    },
    #[error(
        "object 0x{index:04X}:{sub} cannot be written in the present device state: \
         the PDO must be invalid (COB-ID bit 31), its mapping count 0 and the node not OPERATIONAL"
    )]
    DeviceState { index: u16, sub: u8 },
    #[error(
        "mapping entry 0x{entry:08X} written to 0x{index:04X}:{sub} names an object that cannot \
         be mapped to this PDO (must exist, be PDO-mappable in this direction and have its real length)"
    )]
    NotMappable { index: u16, sub: u8, entry: u32 },
    #[error(
        "mapping of 0x{index:04X} with {count} entries has {bits} bits; a PDO holds at most 64"
    )]
    MappingTooLong { index: u16, count: u8, bits: u32 },
    #[error(
        "value {value} (0x{value:X}) written to 0x{index:04X}:{sub} is out of range; allowed {allowed}"
    )]
    ValueRange {
        index: u16,
        sub: u8,
        value: u32,
        allowed: &'static str,
    },
    #[error(
        "SDO command specifier 0x{command:02X} is not supported; allowed expedited 0x2x (download) and 0x40 (upload)"
    )]
    InvalidCommand { command: u8 },
}

impl SdoAbort {
    /// The CiA 301 abort code.
    pub const fn code(&self) -> u32 {
        match self {
            SdoAbort::ObjectDoesNotExist { .. } => 0x0602_0000,
            SdoAbort::SubIndexDoesNotExist { .. } => 0x0609_0011,
            SdoAbort::WriteToReadOnly { .. } => 0x0601_0002,
            SdoAbort::ReadOfWriteOnly { .. } => 0x0601_0001,
            SdoAbort::LengthMismatch { .. } => 0x0607_0010,
            SdoAbort::DeviceState { .. } => 0x0800_0022,
            SdoAbort::NotMappable { .. } => 0x0604_0041,
            SdoAbort::MappingTooLong { .. } => 0x0604_0042,
            SdoAbort::ValueRange { .. } => 0x0609_0030,
            SdoAbort::InvalidCommand { .. } => 0x0504_0001,
        }
    }
}

#[cfg(test)]
mod tests;
