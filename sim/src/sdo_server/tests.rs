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
