use super::*;

fn f(id: u16, d: &[u8]) -> Frame {
    Frame::new(id, d).unwrap()
}

#[test]
fn requests_match_the_reference_bytes() {
    let a = ObjectAddr::new;
    assert_eq!(
        download_request(5, a(0x6060, 0), SdoValue::I8(8)).to_string(),
        "605#2F60600008000000"
    );
    assert_eq!(
        upload_request(5, a(0x6041, 0)).to_string(),
        "605#4041600000000000"
    );
    assert_eq!(
        download_request(5, a(0x6040, 0), SdoValue::U16(0x000F)).to_string(),
        "605#2B4060000F000000"
    );
    assert_eq!(
        download_request(5, a(0x1400, 1), SdoValue::U32(0x8000_0205)).to_string(),
        "605#2300140105020080"
    );
    assert_eq!(
        download_request(5, a(0x1600, 0), SdoValue::U8(0)).to_string(),
        "605#2F00160000000000"
    );
    assert_eq!(
        download_request(5, a(0x1600, 1), SdoValue::U32(0x6040_0010)).to_string(),
        "605#2300160110004060"
    );
    assert_eq!(
        download_request(5, a(0x1400, 2), SdoValue::U8(1)).to_string(),
        "605#2F00140201000000"
    );
    assert_eq!(
        download_request(5, a(0x60C2, 2), SdoValue::I8(-3)).to_string(),
        "605#2FC26002FD000000"
    );
    assert_eq!(
        download_request(5, a(0x6071, 0), SdoValue::I16(-2)).to_string(),
        "605#2B716000FEFF0000"
    );
    assert_eq!(
        abort_frame(5, a(0x2000, 0), 0x0601_0002, true).to_string(),
        "585#8000200002000106"
    );
}

#[test]
fn responses_decode_like_the_reference() {
    assert_eq!(
        decode_response(&f(0x585, &[0x60, 0x60, 0x60, 0, 0, 0, 0, 0])),
        Some(SdoResponse::DownloadAck {
            addr: ObjectAddr::new(0x6060, 0)
        })
    );
    assert_eq!(
        decode_response(&f(0x585, &[0x4B, 0x41, 0x60, 0, 0x37, 0x02, 0, 0])),
        Some(SdoResponse::Upload {
            addr: ObjectAddr::new(0x6041, 0),
            data: 0x0237,
            size: Some(2)
        })
    );
    assert_eq!(
        decode_response(&f(0x585, &[0x42, 0, 0x10, 0, 1, 2, 3, 4])),
        Some(SdoResponse::Upload {
            addr: ObjectAddr::new(0x1000, 0),
            data: 0x0403_0201,
            size: None
        })
    );
    let abort =
        decode_response(&f(0x585, &[0x80, 0x00, 0x20, 0x00, 0x02, 0x00, 0x01, 0x06])).unwrap();
    assert_eq!(
        abort,
        SdoResponse::Abort {
            addr: ObjectAddr::new(0x2000, 0),
            code: SdoAbortCode::WriteToReadOnly
        }
    );
    assert_eq!(decode_response(&f(0x585, &[0x60, 0, 0])), None);
}

#[test]
fn abort_codes_have_texts_and_round_trip() {
    for (code, abort, text) in ABORT_TABLE {
        assert_eq!(SdoAbortCode::from_u32(code), abort);
        assert_eq!(abort.code(), code);
        assert_eq!(abort.text(), text);
    }
    assert_eq!(
        SdoAbortCode::from_u32(0x0800_0022).to_string(),
        "0x08000022 (data cannot be transferred or stored because of the present device state)"
    );
    assert_eq!(
        SdoAbortCode::from_u32(0x1234_5678),
        SdoAbortCode::Other(0x1234_5678)
    );
    assert_eq!(
        SdoAbortCode::Other(0x1234_5678).to_string(),
        "0x12345678 (unknown abort code)"
    );
}

#[test]
fn client_allows_one_transaction_and_matches_the_response() {
    let mut c = SdoClient::new(5, 20_000_000);
    let addr = ObjectAddr::new(0x6041, 0);
    assert_eq!(c.read(0, addr).unwrap().to_string(), "605#4041600000000000");
    assert_eq!(
        c.write(1, ObjectAddr::new(0x6060, 0), SdoValue::I8(8)),
        Err(SdoError::Busy {
            node: 5,
            pending: addr
        })
    );
    // Wrong node, wrong object and wrong kind are ignored.
    assert_eq!(
        c.on_frame(&f(0x586, &[0x4B, 0x41, 0x60, 0, 0x37, 0x02, 0, 0])),
        None
    );
    assert_eq!(
        c.on_frame(&f(0x585, &[0x4B, 0x40, 0x60, 0, 0x37, 0x02, 0, 0])),
        None
    );
    assert_eq!(
        c.on_frame(&f(0x585, &[0x60, 0x41, 0x60, 0, 0, 0, 0, 0])),
        None
    );
    assert!(!c.is_idle());
    let done = c.on_frame(&f(0x585, &[0x4B, 0x41, 0x60, 0, 0x37, 0x02, 0, 0]));
    assert_eq!(
        done,
        Some(Ok(SdoDone::Read {
            addr,
            data: 0x0237,
            size: Some(2)
        }))
    );
    assert!(c.is_idle());
    assert_eq!(
        c.on_frame(&f(0x585, &[0x4B, 0x41, 0x60, 0, 0x37, 0x02, 0, 0])),
        None
    );
}

#[test]
fn client_times_out_exactly_at_the_timeout() {
    let mut c = SdoClient::new(3, 20_000_000);
    let addr = ObjectAddr::new(0x1017, 0);
    c.write(1_000, addr, SdoValue::U16(50)).unwrap();
    assert_eq!(c.poll(1_000 + 19_999_999), None);
    let err = c.poll(1_000 + 20_000_000).unwrap();
    assert_eq!(
        err,
        SdoError::Timeout {
            node: 3,
            addr,
            timeout_ms: 20
        }
    );
    assert_eq!(
        err.to_string(),
        "SDO to node 3: no response for 0x1017:0 within 20 ms"
    );
    assert!(c.is_idle());
    assert_eq!(c.poll(1_000 + 40_000_000), None);
}

#[test]
fn client_reports_aborts_with_their_text() {
    let mut c = SdoClient::new(5, 20_000_000);
    let addr = ObjectAddr::new(0x1600, 1);
    c.write(0, addr, SdoValue::U32(0x6040_0010)).unwrap();
    let abort = abort_frame(5, addr, 0x0800_0022, true);
    let err = c.on_frame(&abort).unwrap().unwrap_err();
    assert_eq!(
        err,
        SdoError::Aborted {
            node: 5,
            addr,
            code: SdoAbortCode::CannotStoreDeviceState
        }
    );
    assert_eq!(
        err.to_string(),
        "SDO to node 5: 0x1600:1 aborted by the drive with code 0x08000022 \
         (data cannot be transferred or stored because of the present device state)"
    );
}

#[test]
fn segmented_upload_is_refused_with_a_clear_error() {
    let mut c = SdoClient::new(5, 20_000_000);
    let addr = ObjectAddr::new(0x1008, 0);
    c.read(0, addr).unwrap();
    let err = c
        .on_frame(&f(0x585, &[0x41, 0x08, 0x10, 0, 12, 0, 0, 0]))
        .unwrap()
        .unwrap_err();
    assert_eq!(
        err,
        SdoError::Segmented {
            node: 5,
            addr,
            size: 12
        }
    );
}
