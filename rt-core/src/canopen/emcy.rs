//! EMCY (emergency) frames: decode `080+n#<code LE><register><5 vendor bytes>` into a
//! readable error naming the code, its class, the error register bits, the node and the axis.
//!
//! Runs inside the cycle: decoding is allocation-free; the texts are `&'static str` and the
//! `Display` output is produced only by whoever prints it (outside the cycle).
//!
//! ```
//! use mcm_rt_core::canopen::emcy::Emcy;
//! let f = mcm_bus::Frame::new(0x083, &[0x30, 0x81, 0x11, 0, 0, 0, 0, 0]).unwrap();
//! let e = Emcy::decode(&f, 2).unwrap();
//! assert_eq!(e.code, 0x8130);
//! assert_eq!(e.to_string(),
//!     "EMCY from node 3 (axis 3): code 0x8130 heartbeat or life-guard error \
//!      (class: communication), error register 0x11 [generic, communication]");
//! ```

use super::objects::EMCY_BASE;
use core::fmt;
use mcm_bus::Frame;

/// EMCY code of the drive profile for safe torque off while enabled: the emergency switch
/// (`docs/drive-profile.md`, "EMCY"). On a real bus it usually arrives before the TPDO1 whose
/// statusword shows the input (bit 14): the EMCY is sent at once, the TPDO1 at the next SYNC.
pub const SAFE_TORQUE_OFF: u16 = 0x5441;

/// A decoded emergency message. `axis` is 0-based (0..6); texts print it 1-based.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Emcy {
    pub node: u8,
    pub axis: usize,
    /// Error code (0x0000 = error reset / no error).
    pub code: u16,
    /// Error register 0x1001.
    pub register: u8,
    /// Manufacturer-specific bytes 3..8.
    pub vendor: [u8; 5],
}

/// A frame on an EMCY COB-ID that is not a valid EMCY.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("EMCY from COB-ID 0x{id:03X} has {len} data bytes; CiA 301 requires 8")]
pub struct EmcyDecodeError {
    pub id: u16,
    pub len: u8,
}

impl Emcy {
    /// Decode an EMCY frame of the drive of `axis` (0-based).
    pub fn decode(frame: &Frame, axis: usize) -> Result<Emcy, EmcyDecodeError> {
        if frame.len != 8 {
            return Err(EmcyDecodeError {
                id: frame.id,
                len: frame.len,
            });
        }
        let d = frame.data;
        Ok(Emcy {
            node: frame.id.wrapping_sub(EMCY_BASE) as u8,
            axis,
            code: u16::from_le_bytes([d[0], d[1]]),
            register: d[2],
            vendor: [d[3], d[4], d[5], d[6], d[7]],
        })
    }

    /// The frame a drive sends for this error.
    pub fn encode(&self) -> Frame {
        let [c0, c1] = self.code.to_le_bytes();
        let v = self.vendor;
        Frame {
            id: EMCY_BASE + u16::from(self.node),
            len: 8,
            data: [c0, c1, self.register, v[0], v[1], v[2], v[3], v[4]],
        }
    }

    /// `true` for code 0x0000 (the drive's error was reset).
    pub fn is_reset(&self) -> bool {
        self.code == 0
    }

    /// Text of the specific code.
    pub fn code_text(&self) -> &'static str {
        code_text(self.code)
    }

    /// Text of the code's class (its upper bits).
    pub fn class_text(&self) -> &'static str {
        class_text(self.code)
    }
}

/// Specific texts for the codes the MCM drives use or that CiA 301/402 define commonly.
pub fn code_text(code: u16) -> &'static str {
    match code {
        0x0000 => "error reset / no error",
        0x1000 => "generic error",
        0x2310 => "continuous over-current",
        0x3210 => "DC-link over-voltage",
        0x3220 => "DC-link under-voltage",
        0x4210 => "excess temperature device",
        0x4310 => "excess temperature drive",
        0x5441 => "safe torque off active (emergency stop)",
        0x6100 => "internal software error",
        0x7121 => "motor blocked",
        0x7305 => "incremental sensor 1 fault",
        0x8100 => "communication error",
        0x8110 => "CAN overrun (objects lost)",
        0x8120 => "CAN in error passive mode",
        0x8130 => "heartbeat or life-guard error",
        0x8140 => "recovered from bus-off",
        0x8150 => "CAN-ID collision",
        0x8210 => "PDO not processed due to length error",
        0x8220 => "PDO length exceeded",
        0x8240 => "unexpected SYNC data length",
        0x8250 => "RPDO timeout",
        0x8611 => "following error",
        0x9000 => "external error",
        0xF000 => "additional functions",
        0xFF00..=0xFFFF => "device-specific error",
        _ => class_text(code),
    }
}

/// Text of the error code class (CiA 301 table).
pub fn class_text(code: u16) -> &'static str {
    match code >> 12 {
        0x0 if code == 0 => "no error",
        0x1 => "generic",
        0x2 => "current",
        0x3 => "voltage",
        0x4 => "temperature",
        0x5 => "device hardware",
        0x6 => "device software",
        0x7 => "additional modules",
        0x8 => match code >> 8 {
            0x81 => "communication",
            0x82 => "protocol error",
            0x86 => "monitoring (CiA 402)",
            _ => "monitoring",
        },
        0x9 => "external error",
        0xF if code >= 0xFF00 => "device specific",
        0xF => "additional functions",
        _ => "unknown class",
    }
}

const REGISTER_BITS: [&str; 8] = [
    "generic",
    "current",
    "voltage",
    "temperature",
    "communication",
    "device profile specific",
    "reserved",
    "manufacturer specific",
];

/// Writes the names of the set error-register bits, comma separated.
pub struct RegisterBits(pub u8);

impl fmt::Display for RegisterBits {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut first = true;
        for (bit, name) in REGISTER_BITS.iter().enumerate() {
            if self.0 & (1 << bit) != 0 {
                if !first {
                    f.write_str(", ")?;
                }
                f.write_str(name)?;
                first = false;
            }
        }
        if first {
            f.write_str("none")?;
        }
        Ok(())
    }
}

impl fmt::Display for Emcy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "EMCY from node {} (axis {}): code 0x{:04X} {} (class: {}), error register 0x{:02X} [{}]",
            self.node,
            self.axis + 1,
            self.code,
            self.code_text(),
            self.class_text(),
            self.register,
            RegisterBits(self.register)
        )?;
        if self.vendor != [0; 5] {
            let v = self.vendor;
            write!(
                f,
                ", vendor data {:02X}{:02X}{:02X}{:02X}{:02X}",
                v[0], v[1], v[2], v[3], v[4]
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
