//! Expedited SDO server of the simulated drive (CiA 301 §7.2.4, the subset of
//! `docs/drive-profile.md`, "Boot and configuration"): decodes a request frame on `0x600 + n`, asks the drive for the
//! object through [`ObjectAccess`], and builds the response on `0x580 + n`.
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
mod tests {
    use super::*;

    /// A two-object mock: 0x2000:0 u16 read-write, 0x2001:0 u8 read-only.
    struct Mock {
        rw: u32,
        writes: u32,
        last_size: Option<Option<u8>>,
    }
    impl ObjectAccess for Mock {
        fn sdo_read(&mut self, index: u16, sub: u8) -> Result<(u32, u8), SdoAbort> {
            match (index, sub) {
                (0x2000, 0) => Ok((self.rw, 2)),
                (0x2001, 0) => Ok((0xAB, 1)),
                (0x2002, 0) => Ok((0xDEAD_BEEF, 4)),
                _ => Err(SdoAbort::ObjectDoesNotExist { index }),
            }
        }
        fn sdo_write(
            &mut self,
            index: u16,
            sub: u8,
            raw: u32,
            size: Option<u8>,
        ) -> Result<(), SdoAbort> {
            self.writes += 1;
            self.last_size = Some(size);
            match (index, sub) {
                (0x2000, 0) => {
                    self.rw = raw;
                    Ok(())
                }
                _ => Err(SdoAbort::WriteToReadOnly { index, sub }),
            }
        }
    }

    fn mock() -> Mock {
        Mock {
            rw: 0,
            writes: 0,
            last_size: None,
        }
    }

    fn req(bytes: [u8; 8]) -> Frame {
        Frame {
            id: 0x603,
            len: 8,
            data: bytes,
        }
    }

    #[test]
    fn expedited_download_and_upload() {
        let mut m = mock();
        let r = serve(
            3,
            &req([0x2B, 0x00, 0x20, 0x00, 0x34, 0x12, 0xFF, 0xFF]),
            &mut m,
        )
        .unwrap();
        assert_eq!(r.to_string(), "583#6000200000000000");
        assert_eq!(m.rw, 0x1234, "bytes past the indicated size are masked off");
        assert_eq!(m.last_size, Some(Some(2)));
        let r = serve(3, &req([0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]), &mut m).unwrap();
        assert_eq!(r.to_string(), "583#4B00200034120000");
        let r = serve(3, &req([0x40, 0x01, 0x20, 0x00, 0, 0, 0, 0]), &mut m).unwrap();
        assert_eq!(r.to_string(), "583#4F012000AB000000");
        let r = serve(3, &req([0x40, 0x02, 0x20, 0x00, 0, 0, 0, 0]), &mut m).unwrap();
        assert_eq!(r.to_string(), "583#43022000EFBEADDE");
    }

    #[test]
    fn size_not_indicated_is_passed_as_none() {
        let mut m = mock();
        serve(
            3,
            &req([0x22, 0x00, 0x20, 0x00, 0x01, 0x00, 0x00, 0x00]),
            &mut m,
        )
        .unwrap();
        assert_eq!(m.last_size, Some(None));
    }

    #[test]
    fn refusals_become_abort_frames() {
        let mut m = mock();
        let r = serve(3, &req([0x2F, 0x01, 0x20, 0x00, 1, 0, 0, 0]), &mut m).unwrap();
        assert_eq!(r.to_string(), "583#8001200002000106");
        let r = serve(3, &req([0x40, 0x99, 0x20, 0x00, 0, 0, 0, 0]), &mut m).unwrap();
        assert_eq!(r.to_string(), "583#8099200000000206");
    }

    #[test]
    fn invalid_command_specifiers_abort_0x05040001() {
        // segmented download initiate, upload segment, block download, ccs 7
        for cs in [0x21u8, 0x60, 0xC0, 0xE0, 0x00] {
            let mut m = mock();
            let r = serve(3, &req([cs, 0x00, 0x20, 0x00, 0, 0, 0, 0]), &mut m).unwrap();
            assert_eq!(&r.data[..4], &[0x80, 0x00, 0x20, 0x00], "cs {cs:02X}");
            assert_eq!(
                u32::from_le_bytes(r.data[4..8].try_into().unwrap()),
                0x0504_0001
            );
            assert_eq!(m.writes, 0);
        }
    }

    #[test]
    fn client_abort_and_short_frames_get_no_answer() {
        let mut m = mock();
        assert_eq!(
            serve(3, &req([0x80, 0x00, 0x20, 0x00, 0, 0, 0, 0]), &mut m),
            None
        );
        let short = Frame::new(0x603, &[0x40, 0x00, 0x20, 0x00]).unwrap();
        assert_eq!(serve(3, &short, &mut m), None);
    }
}
