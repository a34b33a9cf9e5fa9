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

/// Talks to a real interface only when `MCM_TEST_CAN_IFACE` names one (e.g. `vcan0`; the bus must
/// be quiet: nothing else sends on it). The host's kernel has no CAN: `tests/vm/socketcan.rs`
/// runs this test in a virtual machine with `vcan0`, and checks that it passed (not skipped).
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
    let open = || SocketCanBus::open(&iface).unwrap_or_else(|e| panic!("{e}"));
    let (mut a, mut b) = (open(), open());
    let second = 1_000_000_000;
    // Nothing queued: a deadline in the past polls and returns at once.
    while b.recv(0).unwrap().is_some() {}
    assert_eq!(b.recv(0).unwrap(), None);

    // Frames both ways; a socket does not receive its own frames.
    let sdo = Frame::new(0x605, &[0x40, 0x41, 0x60, 0, 0, 0, 0, 0]).unwrap();
    a.send(&sdo).unwrap();
    assert_eq!(b.recv(monotonic_ns() + second).unwrap(), Some(sdo));
    assert_eq!(a.recv(0).unwrap(), None, "a socket received its own frame");
    let reply = Frame::new(0x585, &[0x4B, 0x41, 0x60, 0, 0x37, 0x02, 0, 0]).unwrap();
    b.send(&reply).unwrap();
    assert_eq!(a.recv(monotonic_ns() + second).unwrap(), Some(reply));
    assert_eq!(b.recv(0).unwrap(), None, "a socket received its own frame");
    let empty = Frame::new(0x080, &[]).unwrap();
    a.send(&empty).unwrap();
    assert_eq!(b.recv(monotonic_ns() + second).unwrap(), Some(empty));

    // Frames the MCM does not use (extended ids, remote frames) are skipped and counted; the
    // data frame after them is returned.
    {
        let raw = CanSocket::open(&iface).unwrap();
        let ext = CanFrame::new(Id::Extended(ExtendedId::new(0x1234_5678).unwrap()), &[1]).unwrap();
        raw.write_frame(&ext).unwrap();
        let rtr = CanFrame::new_remote(StandardId::new(0x705).unwrap(), 1).unwrap();
        raw.write_frame(&rtr).unwrap();
        raw.write_frame(&to_can_frame(&sdo).unwrap()).unwrap();
    }
    assert_eq!(b.recv(monotonic_ns() + second).unwrap(), Some(sdo));
    assert_eq!(b.skipped_frames(), 2);

    // With nothing on the bus, recv returns None, and not before its deadline.
    let start = monotonic_ns();
    let got = b.recv(start + 50_000_000).unwrap();
    let waited = monotonic_ns() - start;
    assert_eq!(
        got, None,
        "a frame came from elsewhere on {iface}: this test needs a quiet bus"
    );
    assert!(
        waited >= 50_000_000,
        "recv returned after {waited} ns, before its 50 ms deadline"
    );
    // A frame that comes while recv waits ends the wait at once, long before the deadline.
    let sender = std::thread::spawn(move || {
        std::thread::sleep(std::time::Duration::from_millis(100));
        a.send(&reply).unwrap();
        a
    });
    let start = monotonic_ns();
    let got = b.recv(start + 30 * second).unwrap();
    let waited = monotonic_ns() - start;
    let mut a = sender.join().unwrap();
    assert_eq!(got, Some(reply));
    assert!(
        waited < 10 * second,
        "recv took {waited} ns for a frame sent after 100 ms (its deadline was 30 s)"
    );

    // send never blocks: a burst far beyond the socket buffers, with nobody reading, either
    // goes out or says the transmit queue is full. The reader then finds the frames in order,
    // from the first on (the kernel drops what its receive buffer cannot hold, at the end).
    let burst = 5_000u32;
    let mut full = 0;
    for i in 0..burst {
        match a.send(&Frame::new(0x181, &i.to_le_bytes()).unwrap()) {
            Ok(()) => {}
            Err(BusError::TxQueueFull { .. }) => full += 1,
            Err(e) => panic!("frame {i} of the burst: {e}"),
        }
    }
    let mut expected = 0u32;
    while let Some(f) = b.recv(0).unwrap() {
        assert_eq!(f.id, 0x181, "{f:?}");
        let seq = u32::from_le_bytes(f.payload().try_into().unwrap());
        assert_eq!(
            seq, expected,
            "the burst's frames out of order or with a gap"
        );
        expected += 1;
    }
    println!("burst of {burst} frames: {full} refused (transmit queue full), {expected} received");
    assert!(expected > 0, "none of the burst's frames arrived");
    assert!(u64::from(expected) + full <= u64::from(burst));
}
