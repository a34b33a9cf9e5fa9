use super::*;
use ::socketcan::{ExtendedId, Id};

#[test]
fn frames_convert_both_ways() {
    for f in [
        Frame::new(0x080, &[]).unwrap(),
        Frame::new(0x185, &[0x37, 0x02, 0xA0, 0x86, 0x01, 0x00, 0xFE, 0xFF]).unwrap(),
        Frame::new(0x7FF, &[1]).unwrap(),
    ] {
        let cf = to_can_frame(&f).unwrap();
        assert_eq!(cf.raw_id(), u32::from(f.id));
        assert_eq!(cf.data(), f.payload());
        assert!(!cf.is_extended());
        assert_eq!(from_can_frame(&cf), Ok(f));
    }
}

#[test]
fn unusable_frames_are_typed_errors() {
    let ext = CanFrame::new(Id::Extended(ExtendedId::new(0x1234_5678).unwrap()), &[1, 2]).unwrap();
    assert_eq!(
        from_can_frame(&ext),
        Err(FrameConversionError::ExtendedId { id: 0x1234_5678 })
    );
    let rtr = CanFrame::new_remote(StandardId::new(0x705).unwrap(), 1).unwrap();
    assert_eq!(
        from_can_frame(&rtr),
        Err(FrameConversionError::Remote { id: 0x705 })
    );
    let bad = Frame {
        id: 0x800,
        len: 0,
        data: [0; 8],
    };
    assert_eq!(
        to_can_frame(&bad).unwrap_err().to_string(),
        "frame with id 0x800 and length 0 is not a classic CAN frame; allowed: id <= 0x7FF, length <= 8"
    );
    let long = Frame {
        id: 0x100,
        len: 9,
        data: [0; 8],
    };
    assert!(to_can_frame(&long).is_err());
}

#[test]
fn bad_interface_names_are_refused() {
    for name in ["", "a/b", "can 0", "sixteen_chars_xx"] {
        let err = SocketCanBus::open(name).unwrap_err();
        assert!(
            matches!(err, SocketCanError::BadName { .. }),
            "{name:?}: {err}"
        );
    }
}

#[test]
fn opening_a_missing_interface_names_it_and_the_os_error() {
    let err = SocketCanBus::open("mcmnocan7").unwrap_err();
    let msg = err.to_string();
    println!("{msg}");
    assert!(msg.contains("mcmnocan7"), "{msg}");
    assert!(msg.contains("os error"), "{msg}");
    match check_kernel_support("mcmnocan7") {
        Err(SocketCanError::NoKernelSupport { .. }) => {
            // This machine has no CAN in its kernel (errno 97): that must be the error.
            assert!(
                matches!(err, SocketCanError::NoKernelSupport { .. }),
                "{err:?}"
            );
            assert!(
                msg.contains("os error 97") && msg.contains("EAFNOSUPPORT"),
                "{msg}"
            );
        }
        _ => assert!(
            matches!(
                err,
                SocketCanError::NoSuchInterface {
                    errno: libc::ENODEV,
                    ..
                }
            ),
            "{err:?}"
        ),
    }
}

/// Talks to a real interface only when `MCM_TEST_CAN_IFACE` names one (e.g. `vcan0`).
#[test]
fn real_interface_round_trip_when_available() {
    let Ok(iface) = std::env::var("MCM_TEST_CAN_IFACE") else {
        let kernel = match check_kernel_support("vcan0") {
            Ok(()) => "this kernel supports CAN".to_owned(),
            Err(e) => e.to_string(),
        };
        println!(
            "skipped: MCM_TEST_CAN_IFACE is not set (set it to an existing CAN or vcan interface, \
             e.g. vcan0, to run this test); {kernel}"
        );
        return;
    };
    let mut a = SocketCanBus::open(&iface).unwrap_or_else(|e| panic!("{e}"));
    let mut b = SocketCanBus::open(&iface).unwrap_or_else(|e| panic!("{e}"));
    // Nothing queued: a deadline in the past polls and returns at once.
    while b.recv(0).unwrap().is_some() {}
    assert_eq!(b.recv(0).unwrap(), None);
    let f = Frame::new(0x605, &[0x40, 0x41, 0x60, 0, 0, 0, 0, 0]).unwrap();
    a.send(&f).unwrap();
    let got = b.recv(monotonic_ns() + 1_000_000_000).unwrap();
    assert_eq!(got, Some(f));
    // With nothing on the bus, recv returns None, and not before its deadline.
    let start = monotonic_ns();
    if b.recv(start + 20_000_000).unwrap().is_none() {
        assert!(monotonic_ns() >= start + 20_000_000);
    }
}
