//! Expedited SDO server of the simulated drive (CiA 301 §7.2.4, the subset of
//! `docs/drive-profile.md`, "Boot and configuration"): decodes a request frame on `0x600 + n`, asks
//! the drive for the object through [`ObjectAccess`], and builds the response on `0x580 + n`.
//!
//! Runs inside the cycle: pure, no allocation. The object semantics (access rights, lengths,
//! PDO-mapping rules, value ranges) live in the drive's [`ObjectAccess`] implementation; this
//! module only speaks the protocol:
//! - download (write) `0x22..=0x2F` with the expedited bit: response `0x60`, or abort `0x80`;
//! - upload (read) `0x40`: response `0x43`/`0x47`/`0x4B`/`0x4F` by size, or abort;
//! - a client abort (`0x80`) gets no answer; any other command specifier (segmented and block
//!   transfers included) is aborted with 0x05040001;
//! - a request whose DLC is not 8 is ignored (CiA 301 requires DLC 8), as real drives do.
//!
//! ```
//! use mcm_bus::Frame;
//! use mcm_sim::{sdo_server, SdoAbort};
//! struct One(u32);
//! impl sdo_server::ObjectAccess for One {
//!     fn sdo_read(&mut self, _i: u16, _s: u8) -> Result<(u32, u8), SdoAbort> { Ok((self.0, 2)) }
//!     fn sdo_write(&mut self, i: u16, s: u8, _v: u32, _n: Option<u8>) -> Result<(), SdoAbort> {
//!         Err(SdoAbort::WriteToReadOnly { index: i, sub: s })
//!     }
//! }
//! let req = Frame::new(0x605, &[0x40, 0x41, 0x60, 0, 0, 0, 0, 0]).unwrap();
//! let resp = sdo_server::serve(5, &req, &mut One(0x0237)).unwrap();
//! assert_eq!(resp.to_string(), "585#4B41600037020000");
//! ```

use super::abort::SdoAbort;
use mcm_bus::Frame;

/// COB-ID base of SDO requests (client -> server).
pub const SDO_RX_BASE: u16 = 0x600;
/// COB-ID base of SDO responses (server -> client).
pub const SDO_TX_BASE: u16 = 0x580;

/// Object access with the drive's semantics, called by [`serve`].
pub trait ObjectAccess {
    /// Read `index:sub`: the raw value and its size in bytes (1, 2 or 4).
    fn sdo_read(&mut self, index: u16, sub: u8) -> Result<(u32, u8), SdoAbort>;
    /// Write `index:sub` with `raw` (the request's data bytes, little-endian, masked to
    /// `size` bytes); `size` is `None` when the request did not indicate it.
    fn sdo_write(
        &mut self,
        index: u16,
        sub: u8,
        raw: u32,
        size: Option<u8>,
    ) -> Result<(), SdoAbort>;
}

/// Serve one request addressed to this node (`frame.id == 0x600 + node_id`). Returns the
/// response frame, or `None` when none is due (client abort, wrong DLC).
pub fn serve(node_id: u8, req: &Frame, objects: &mut dyn ObjectAccess) -> Option<Frame> {
    if req.len != 8 {
        return None;
    }
    let d = &req.data;
    let cs = d[0];
    let index = u16::from_le_bytes([d[1], d[2]]);
    let sub = d[3];
    let value = u32::from_le_bytes([d[4], d[5], d[6], d[7]]);
    let result = match cs >> 5 {
        // initiate download; only expedited (e = bit 1) is served
        1 if cs & 0x02 != 0 => {
            let size = (cs & 0x01 != 0).then(|| 4 - ((cs >> 2) & 0x03));
            let masked = match size {
                Some(n) if n < 4 => value & ((1u32 << (8 * u32::from(n))) - 1),
                _ => value,
            };
            objects
                .sdo_write(index, sub, masked, size)
                .map(|()| (0x60, 0))
        }
        // initiate upload
        2 => objects
            .sdo_read(index, sub)
            .map(|(raw, size)| (0x43 | ((4 - size.clamp(1, 4)) << 2), raw)),
        // abort transfer from the client: nothing to answer
        4 => return None,
        _ => Err(SdoAbort::InvalidCommand { command: cs }),
    };
    let (command, payload) = match result {
        Ok(ok) => ok,
        Err(abort) => (0x80, abort.code()),
    };
    let mut data = [0u8; 8];
    data[0] = command;
    data[1..3].copy_from_slice(&index.to_le_bytes());
    data[3] = sub;
    data[4..8].copy_from_slice(&payload.to_le_bytes());
    Some(Frame {
        id: SDO_TX_BASE + u16::from(node_id),
        len: 8,
        data,
    })
}

#[cfg(test)]
mod tests;
