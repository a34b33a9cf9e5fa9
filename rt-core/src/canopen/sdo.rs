//! Expedited SDO client (CiA 301): frame encoding/decoding, typed abort codes with their
//! texts, and a per-node client that allows one outstanding transaction and times it out.
//!
//! Runs inside the cycle (only for the boot configuration of nodes that are not operational):
//! no allocation, no blocking. Time is the `now_ns` the caller passes in.
//!
//! ```
//! use mcm_rt_core::canopen::objects::ObjectAddr;
//! use mcm_rt_core::canopen::sdo::{SdoClient, SdoValue};
//! let mut sdo = SdoClient::new(5, 50_000_000);
//! let req = sdo.write(0, ObjectAddr::new(0x6060, 0), SdoValue::I8(8)).unwrap();
//! assert_eq!(req.to_string(), "605#2F60600008000000");
//! let resp = mcm_bus::Frame::new(0x585, &[0x60, 0x60, 0x60, 0, 0, 0, 0, 0]).unwrap();
//! assert!(matches!(sdo.on_frame(&resp), Some(Ok(_))));
//! ```

use super::objects::{ObjectAddr, sdo_rx_id, sdo_tx_id};
use mcm_bus::Frame;

/// A value written by an expedited download; the variant fixes the size (1, 2 or 4 bytes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdoValue {
    U8(u8),
    I8(i8),
    U16(u16),
    I16(i16),
    U32(u32),
    I32(i32),
}

impl SdoValue {
    /// Size in bytes.
    pub const fn size(self) -> u8 {
        match self {
            SdoValue::U8(_) | SdoValue::I8(_) => 1,
            SdoValue::U16(_) | SdoValue::I16(_) => 2,
            SdoValue::U32(_) | SdoValue::I32(_) => 4,
        }
    }

    /// The value as the little-endian u32 carried in bytes 4..8.
    pub const fn raw(self) -> u32 {
        match self {
            SdoValue::U8(v) => v as u32,
            SdoValue::I8(v) => v as u8 as u32,
            SdoValue::U16(v) => v as u32,
            SdoValue::I16(v) => v as u16 as u32,
            SdoValue::U32(v) => v,
            SdoValue::I32(v) => v as u32,
        }
    }
}

/// SDO abort codes (CiA 301) with their texts. Unlisted codes are kept as `Other`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdoAbortCode {
    ToggleBitNotAlternated,
    ProtocolTimedOut,
    CommandSpecifierInvalid,
    OutOfMemory,
    UnsupportedAccess,
    ReadOfWriteOnly,
    WriteToReadOnly,
    ObjectDoesNotExist,
    ObjectCannotBeMapped,
    MappingExceedsPdoLength,
    GeneralParameterIncompatibility,
    InternalIncompatibility,
    HardwareError,
    TypeLengthMismatch,
    TypeLengthTooHigh,
    TypeLengthTooLow,
    SubIndexDoesNotExist,
    ValueRangeExceeded,
    ValueTooHigh,
    ValueTooLow,
    MaxBelowMin,
    ResourceNotAvailable,
    GeneralError,
    CannotStore,
    CannotStoreLocalControl,
    CannotStoreDeviceState,
    NoObjectDictionary,
    Other(u32),
}

const ABORT_TABLE: [(u32, SdoAbortCode, &str); 27] = [
    (
        0x0503_0000,
        SdoAbortCode::ToggleBitNotAlternated,
        "toggle bit not alternated",
    ),
    (
        0x0504_0000,
        SdoAbortCode::ProtocolTimedOut,
        "SDO protocol timed out",
    ),
    (
        0x0504_0001,
        SdoAbortCode::CommandSpecifierInvalid,
        "command specifier invalid or unknown",
    ),
    (0x0504_0005, SdoAbortCode::OutOfMemory, "out of memory"),
    (
        0x0601_0000,
        SdoAbortCode::UnsupportedAccess,
        "unsupported access to an object",
    ),
    (
        0x0601_0001,
        SdoAbortCode::ReadOfWriteOnly,
        "attempt to read a write-only object",
    ),
    (
        0x0601_0002,
        SdoAbortCode::WriteToReadOnly,
        "attempt to write a read-only object",
    ),
    (
        0x0602_0000,
        SdoAbortCode::ObjectDoesNotExist,
        "object does not exist in the object dictionary",
    ),
    (
        0x0604_0041,
        SdoAbortCode::ObjectCannotBeMapped,
        "object cannot be mapped to the PDO",
    ),
    (
        0x0604_0042,
        SdoAbortCode::MappingExceedsPdoLength,
        "mapped objects would exceed the PDO length",
    ),
    (
        0x0604_0043,
        SdoAbortCode::GeneralParameterIncompatibility,
        "general parameter incompatibility",
    ),
    (
        0x0604_0047,
        SdoAbortCode::InternalIncompatibility,
        "general internal incompatibility in the device",
    ),
    (
        0x0606_0000,
        SdoAbortCode::HardwareError,
        "access failed due to a hardware error",
    ),
    (
        0x0607_0010,
        SdoAbortCode::TypeLengthMismatch,
        "data type does not match, length of service parameter does not match",
    ),
    (
        0x0607_0012,
        SdoAbortCode::TypeLengthTooHigh,
        "data type does not match, length of service parameter too high",
    ),
    (
        0x0607_0013,
        SdoAbortCode::TypeLengthTooLow,
        "data type does not match, length of service parameter too low",
    ),
    (
        0x0609_0011,
        SdoAbortCode::SubIndexDoesNotExist,
        "sub-index does not exist",
    ),
    (
        0x0609_0030,
        SdoAbortCode::ValueRangeExceeded,
        "value range of parameter exceeded",
    ),
    (
        0x0609_0031,
        SdoAbortCode::ValueTooHigh,
        "value of parameter written too high",
    ),
    (
        0x0609_0032,
        SdoAbortCode::ValueTooLow,
        "value of parameter written too low",
    ),
    (
        0x0609_0036,
        SdoAbortCode::MaxBelowMin,
        "maximum value is less than minimum value",
    ),
    (
        0x060A_0023,
        SdoAbortCode::ResourceNotAvailable,
        "resource not available",
    ),
    (0x0800_0000, SdoAbortCode::GeneralError, "general error"),
    (
        0x0800_0020,
        SdoAbortCode::CannotStore,
        "data cannot be transferred or stored to the application",
    ),
    (
        0x0800_0021,
        SdoAbortCode::CannotStoreLocalControl,
        "data cannot be transferred or stored because of local control",
    ),
    (
        0x0800_0022,
        SdoAbortCode::CannotStoreDeviceState,
        "data cannot be transferred or stored because of the present device state",
    ),
    (
        0x0800_0023,
        SdoAbortCode::NoObjectDictionary,
        "object dictionary not present or dynamic generation failed",
    ),
];

impl SdoAbortCode {
    pub fn from_u32(code: u32) -> SdoAbortCode {
        ABORT_TABLE
            .iter()
            .find(|(c, _, _)| *c == code)
            .map_or(SdoAbortCode::Other(code), |(_, a, _)| *a)
    }

    pub fn code(self) -> u32 {
        match self {
            SdoAbortCode::Other(c) => c,
            a => ABORT_TABLE
                .iter()
                .find(|(_, t, _)| *t == a)
                .map_or(0, |(c, _, _)| *c),
        }
    }

    /// The CiA 301 text of the code.
    pub fn text(self) -> &'static str {
        match self {
            SdoAbortCode::Other(_) => "unknown abort code",
            a => ABORT_TABLE
                .iter()
                .find(|(_, t, _)| *t == a)
                .map_or("unknown abort code", |(_, _, s)| s),
        }
    }
}

/// `0x06010002 (attempt to write a read-only object)`.
impl core::fmt::Display for SdoAbortCode {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "0x{:08X} ({})", self.code(), self.text())
    }
}

/// Expedited download (write) request.
pub fn download_request(node: u8, addr: ObjectAddr, value: SdoValue) -> Frame {
    let cs = 0x23 | ((4 - value.size()) << 2);
    let [i0, i1] = addr.index.to_le_bytes();
    let [d0, d1, d2, d3] = value.raw().to_le_bytes();
    Frame {
        id: sdo_rx_id(node),
        len: 8,
        data: [cs, i0, i1, addr.sub, d0, d1, d2, d3],
    }
}

/// Upload (read) request.
pub fn upload_request(node: u8, addr: ObjectAddr) -> Frame {
    let [i0, i1] = addr.index.to_le_bytes();
    Frame {
        id: sdo_rx_id(node),
        len: 8,
        data: [0x40, i0, i1, addr.sub, 0, 0, 0, 0],
    }
}

/// Abort transfer frame (either direction; `tx` = sent by the server).
pub fn abort_frame(node: u8, addr: ObjectAddr, code: u32, from_server: bool) -> Frame {
    let id = if from_server {
        sdo_tx_id(node)
    } else {
        sdo_rx_id(node)
    };
    let [i0, i1] = addr.index.to_le_bytes();
    let [c0, c1, c2, c3] = code.to_le_bytes();
    Frame {
        id,
        len: 8,
        data: [0x80, i0, i1, addr.sub, c0, c1, c2, c3],
    }
}

/// A decoded server response.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdoResponse {
    /// `60`: download confirmed.
    DownloadAck { addr: ObjectAddr },
    /// `4x`: expedited upload; `size` is `None` when the server did not indicate it.
    Upload {
        addr: ObjectAddr,
        data: u32,
        size: Option<u8>,
    },
    /// `41`: segmented upload initiated (not supported by this client).
    SegmentedUpload { addr: ObjectAddr, size: u32 },
    /// `80`: transfer aborted.
    Abort {
        addr: ObjectAddr,
        code: SdoAbortCode,
    },
}

/// Decode a frame from `0x580+n`. `None` if it is not an 8-byte initiate/abort response.
pub fn decode_response(frame: &Frame) -> Option<SdoResponse> {
    if frame.len != 8 {
        return None;
    }
    let d = frame.data;
    let addr = ObjectAddr::new(u16::from_le_bytes([d[1], d[2]]), d[3]);
    let value = u32::from_le_bytes([d[4], d[5], d[6], d[7]]);
    let cs = d[0];
    match cs >> 5 {
        3 if cs == 0x60 => Some(SdoResponse::DownloadAck { addr }),
        2 => {
            let expedited = cs & 0x02 != 0;
            let size_indicated = cs & 0x01 != 0;
            if expedited {
                let size = size_indicated.then_some(4 - ((cs >> 2) & 0x03));
                Some(SdoResponse::Upload {
                    addr,
                    data: value,
                    size,
                })
            } else {
                Some(SdoResponse::SegmentedUpload { addr, size: value })
            }
        }
        4 if cs == 0x80 => Some(SdoResponse::Abort {
            addr,
            code: SdoAbortCode::from_u32(value),
        }),
        _ => None,
    }
}

/// What the one outstanding transaction is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdoRequest {
    Read(ObjectAddr),
    Write(ObjectAddr, SdoValue),
}

impl SdoRequest {
    pub fn addr(self) -> ObjectAddr {
        match self {
            SdoRequest::Read(a) | SdoRequest::Write(a, _) => a,
        }
    }
}

/// A finished transaction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdoDone {
    Written(ObjectAddr),
    Read {
        addr: ObjectAddr,
        data: u32,
        size: Option<u8>,
    },
}

/// Why an SDO transaction failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum SdoError {
    #[error(
        "SDO to node {node}: a transaction on {pending} is still outstanding; one at a time per node"
    )]
    Busy { node: u8, pending: ObjectAddr },
    #[error("SDO to node {node}: no response for {addr} within {timeout_ms} ms")]
    Timeout {
        node: u8,
        addr: ObjectAddr,
        timeout_ms: u64,
    },
    #[error("SDO to node {node}: {addr} aborted by the drive with code {code}")]
    Aborted {
        node: u8,
        addr: ObjectAddr,
        code: SdoAbortCode,
    },
    #[error(
        "SDO to node {node}: {addr} answered with a segmented transfer of {size} bytes; only expedited (<= 4 bytes) is supported"
    )]
    Segmented {
        node: u8,
        addr: ObjectAddr,
        size: u32,
    },
}

/// Expedited SDO client for one node: at most one transaction outstanding.
#[derive(Debug, Clone)]
pub struct SdoClient {
    node: u8,
    timeout_ns: u64,
    pending: Option<(SdoRequest, u64)>,
}

impl SdoClient {
    pub fn new(node: u8, timeout_ns: u64) -> SdoClient {
        SdoClient {
            node,
            timeout_ns,
            pending: None,
        }
    }

    pub fn node(&self) -> u8 {
        self.node
    }

    pub fn is_idle(&self) -> bool {
        self.pending.is_none()
    }

    /// Forget the outstanding transaction (e.g. the node rebooted).
    pub fn cancel(&mut self) {
        self.pending = None;
    }

    /// Start a transaction; the returned frame has to be sent.
    pub fn start(&mut self, now_ns: u64, req: SdoRequest) -> Result<Frame, SdoError> {
        if let Some((p, _)) = self.pending {
            return Err(SdoError::Busy {
                node: self.node,
                pending: p.addr(),
            });
        }
        self.pending = Some((req, now_ns));
        Ok(match req {
            SdoRequest::Read(a) => upload_request(self.node, a),
            SdoRequest::Write(a, v) => download_request(self.node, a, v),
        })
    }

    pub fn read(&mut self, now_ns: u64, addr: ObjectAddr) -> Result<Frame, SdoError> {
        self.start(now_ns, SdoRequest::Read(addr))
    }

    pub fn write(
        &mut self,
        now_ns: u64,
        addr: ObjectAddr,
        value: SdoValue,
    ) -> Result<Frame, SdoError> {
        self.start(now_ns, SdoRequest::Write(addr, value))
    }

    /// Feed a frame from `0x580+node`. Returns the outcome when it completes the outstanding
    /// transaction; responses for another object or of the wrong kind are ignored (`None`).
    pub fn on_frame(&mut self, frame: &Frame) -> Option<Result<SdoDone, SdoError>> {
        if frame.id != sdo_tx_id(self.node) {
            return None;
        }
        let (req, _) = self.pending?;
        let resp = decode_response(frame)?;
        let node = self.node;
        let outcome = match (req, resp) {
            (SdoRequest::Write(a, _), SdoResponse::DownloadAck { addr }) if a == addr => {
                Ok(SdoDone::Written(a))
            }
            (SdoRequest::Read(a), SdoResponse::Upload { addr, data, size }) if a == addr => {
                Ok(SdoDone::Read {
                    addr: a,
                    data,
                    size,
                })
            }
            (SdoRequest::Read(a), SdoResponse::SegmentedUpload { addr, size }) if a == addr => {
                Err(SdoError::Segmented {
                    node,
                    addr: a,
                    size,
                })
            }
            (r, SdoResponse::Abort { addr, code }) if r.addr() == addr => {
                Err(SdoError::Aborted { node, addr, code })
            }
            _ => return None,
        };
        self.pending = None;
        Some(outcome)
    }

    /// The timeout error, once, when the outstanding transaction is `timeout` old.
    pub fn poll(&mut self, now_ns: u64) -> Option<SdoError> {
        let (req, since) = self.pending?;
        if now_ns.saturating_sub(since) >= self.timeout_ns {
            self.pending = None;
            return Some(SdoError::Timeout {
                node: self.node,
                addr: req.addr(),
                timeout_ms: self.timeout_ns / 1_000_000,
            });
        }
        None
    }
}

#[cfg(test)]
mod tests;
