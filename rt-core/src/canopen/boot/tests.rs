use super::*;
use crate::canopen::sdo::{abort_frame, decode_response};
use crate::canopen::testdrive::{FakeDrive, Fault};

const MS: u64 = 1_000_000;

fn params() -> BootParams {
    BootParams {
        node: 3,
        axis: 2,
        drive_heartbeat_ms: 50,
        master_node_id: 127,
        master_heartbeat_timeout_ms: 150,
        cycle_ms: 5,
        rated_current_ma: 4000,
        rated_torque_mnm: 480,
        max_current_permille: 2500,
    }
}

/// Run the sequence against the fake drive, one cycle per 5 ms; the drive answers in the
/// next cycle. Returns the frames sent and the final output.
fn run(drive: &mut FakeDrive, cycles: usize) -> (Vec<Frame>, BootOutput) {
    let mut seq = BootSequence::new(&params());
    let mut sdo = SdoClient::new(3, 50 * MS);
    seq.start(StoredCalibration::Read);
    let mut sent = Vec::new();
    let mut inbox: Vec<Frame> = Vec::new();
    for k in 0..cycles {
        let now = k as u64 * 5 * MS;
        let mut outcome = None;
        for f in inbox.drain(..) {
            if let Some(o) = sdo.on_frame(&f) {
                outcome = Some(o);
            }
        }
        let out = seq.poll(now, &mut sdo, outcome);
        match out {
            BootOutput::Send(f) => {
                sent.push(f);
                inbox.extend(drive.receive(&f));
            }
            BootOutput::Done(f) => {
                sent.push(f);
                drive.receive(&f);
                return (sent, out);
            }
            BootOutput::Failed(_) => return (sent, out),
            BootOutput::Waiting | BootOutput::Idle => {}
        }
    }
    (sent, BootOutput::Waiting)
}

#[test]
fn sequence_is_exactly_the_drive_profile() {
    let mut drive = FakeDrive::new(3);
    let (sent, out) = run(&mut drive, 200);
    assert_eq!(out, BootOutput::Done(nmt_frame(NmtCommand::Start, 3)));
    let text: Vec<String> = sent.iter().map(|f| f.to_string()).collect();
    let expected = [
        "603#4000100000000000", // 1. read 0x1000
        "603#2B17100032000000", // 2. 0x1017 = 50
        "603#2316100196007F00", // 3. 0x1016:1 = 127 << 16 | 150
        "603#2300140103020080", // 4.
        "603#2F00160000000000",
        "603#2300160110004060",
        "603#2300160220007A60",
        "603#2300160310007160",
        "603#2F00160003000000",
        "603#2F00140201000000",
        "603#2300140103020000",
        "603#2301140103030080", // 5.
        "603#2F01160000000000",
        "603#2301160108006060",
        "603#2301160210007360",
        "603#230116031000B260",
        "603#2F01160003000000",
        "603#2F011402FF000000",
        "603#2301140103030000",
        "603#2300180183010080", // 6.
        "603#2F001A0000000000",
        "603#23001A0110004160",
        "603#23001A0220006460",
        "603#23001A0310007860",
        "603#2F001A0003000000",
        "603#2F00180201000000",
        "603#2300180183010000",
        "603#2301180183020080", // 7.
        "603#2F011A0000000000",
        "603#23011A0108006160",
        "603#2F011A0001000000",
        "603#2F011802FF000000",
        "603#2B01180564000000", //    0x1801:5 event timer = 100 ms
        "603#2301180183020000",
        "603#2FC2600105000000", // 8.
        "603#2FC26002FD000000",
        "603#23756000A00F0000", // 9. 4000 mA
        "603#23766000E0010000",
        "603#2B736000C4090000", // 10. 2500
        "603#2B5A600002000000", // 11. 0x605A = 2
        "603#2B07600002000000", //     0x6007 = 2
        "603#2F60600008000000", //     0x6060 = 8
        "603#4000210200000000", // 12. read 0x2100:2 (not valid: offset not read)
        "000#0103",             // NMT start
    ];
    assert_eq!(text, expected);
    assert!(drive.nmt_started());
    assert_eq!(drive.object(0x1016, 1), Some((127 << 16) | 150));
    assert_eq!(drive.object(0x6076, 0), Some(480));
    assert_eq!(drive.object(0x605A, 0), Some(2));
    assert_eq!(drive.object(0x6007, 0), Some(2));
}

#[test]
fn a_drive_without_the_quick_stop_option_code_fails_the_boot_naming_it() {
    // No such object (0x06020000), and a value the drive does not support (0x06090030).
    for (code, text) in [
        (
            0x0602_0000,
            "SDO abort 0x06020000 (object does not exist in the object dictionary)",
        ),
        (
            0x0609_0030,
            "SDO abort 0x06090030 (value range of parameter exceeded)",
        ),
    ] {
        let mut drive = FakeDrive::new(3);
        drive.script(0x605A, 0, Fault::Abort(code), 3);
        let (_, out) = run(&mut drive, 300);
        let BootOutput::Failed(err) = out else {
            panic!("{out:?}")
        };
        assert_eq!((err.step, err.attempts), (11, 3));
        assert_eq!(
            err.to_string(),
            format!(
                "node 3 (axis 3) configuration step 11 (0x605A:0 quick stop option code = 2 \
                 (quick-stop ramp, then SWITCH ON DISABLED)) failed after 3 attempt(s): {text}"
            )
        );
        assert!(!drive.nmt_started());
    }
}

#[test]
fn stored_calibration_is_read_before_the_nmt_start() {
    let mut drive = FakeDrive::new(3);
    drive.set_object(0x2100, 1, (-7_654_321i32) as u32);
    drive.set_object(0x2100, 2, 1);
    let mut seq = BootSequence::new(&params());
    let mut sdo = SdoClient::new(3, 50 * MS);
    seq.start(StoredCalibration::Read);
    let mut sent = Vec::new();
    let mut inbox: Vec<Frame> = Vec::new();
    for k in 0..200 {
        let mut outcome = None;
        for f in inbox.drain(..) {
            outcome = sdo.on_frame(&f).or(outcome);
        }
        match seq.poll(k * 5 * MS, &mut sdo, outcome) {
            BootOutput::Send(f) => {
                sent.push(f.to_string());
                inbox.extend(drive.receive(&f));
            }
            BootOutput::Done(f) => {
                sent.push(f.to_string());
                break;
            }
            other => assert!(matches!(other, BootOutput::Waiting), "{other:?}"),
        }
    }
    assert_eq!(
        sent[BOOT_OPS..],
        ["603#4000210200000000", "603#4000210100000000", "000#0103"]
    );
    assert_eq!(seq.calibration(), Some(-7_654_321));
    // Valid = 0: no offset read, not calibrated.
    let mut drive = FakeDrive::new(3);
    drive.set_object(0x2100, 1, 99);
    drive.set_object(0x2100, 2, 0);
    let (sent, out) = run(&mut drive, 200);
    assert!(matches!(out, BootOutput::Done(_)));
    assert_eq!(sent.len(), BOOT_OPS + 2);
    // A drive without 0x2100 aborts the read: booted, not calibrated, no retry.
    let mut drive = FakeDrive::new(3);
    drive.script(0x2100, 2, Fault::Abort(0x0602_0000), 1);
    let (sent, out) = run(&mut drive, 200);
    assert!(matches!(out, BootOutput::Done(_)), "{out:?}");
    assert_eq!(sent.len(), BOOT_OPS + 2);
    // A timeout is retried like any step and then fails the boot.
    let mut drive = FakeDrive::new(3);
    drive.script(0x2100, 2, Fault::Silent, 3);
    let (_, out) = run(&mut drive, 300);
    let BootOutput::Failed(err) = out else {
        panic!("{out:?}")
    };
    assert_eq!((err.step, err.attempts), (12, 3));
    assert!(
        err.to_string()
            .contains("0x2100:2 stored calibration valid"),
        "{err}"
    );
}

#[test]
fn aborts_are_retried_twice_then_reported_with_their_text() {
    let mut drive = FakeDrive::new(3);
    drive.script(0x1600, 1, Fault::Abort(0x0800_0022), 2);
    let (_, out) = run(&mut drive, 200);
    assert!(
        matches!(out, BootOutput::Done(_)),
        "two aborts are retried: {out:?}"
    );

    let mut drive = FakeDrive::new(3);
    drive.script(0x1600, 1, Fault::Abort(0x0800_0022), 3);
    let (sent, out) = run(&mut drive, 200);
    let BootOutput::Failed(err) = out else {
        panic!("{out:?}")
    };
    assert_eq!(err.step, 4);
    assert_eq!(err.attempts, 3);
    assert_eq!(
        sent.iter()
            .filter(|f| f.data[1..4] == [0x00, 0x16, 0x01])
            .count(),
        3
    );
    assert_eq!(
        err.to_string(),
        "node 3 (axis 3) configuration step 4 (0x1600:1 RPDO1 mapping 1: controlword) failed after \
         3 attempt(s): SDO abort 0x08000022 (data cannot be transferred or stored because of the \
         present device state)"
    );
}

#[test]
fn timeouts_are_retried_and_reported() {
    let mut drive = FakeDrive::new(3);
    drive.script(0x1017, 0, Fault::Silent, 3);
    let (sent, out) = run(&mut drive, 200);
    let BootOutput::Failed(err) = out else {
        panic!("{out:?}")
    };
    assert_eq!((err.node, err.axis, err.step, err.attempts), (3, 2, 2, 3));
    assert_eq!(err.cause, BootCause::Timeout { timeout_ms: 50 });
    assert_eq!(sent.len(), 1 + 3);
    assert!(
        err.to_string()
            .contains("step 2 (0x1017:0 drive heartbeat producer time)"),
        "{err}"
    );
    assert!(
        err.to_string().ends_with("no SDO response within 50 ms"),
        "{err}"
    );
}

#[test]
fn wrong_device_type_fails_at_once() {
    let mut drive = FakeDrive::new(3);
    drive.set_object(0x1000, 0, 0x0004_0191);
    let (sent, out) = run(&mut drive, 200);
    assert_eq!(sent.len(), 1);
    let BootOutput::Failed(err) = out else {
        panic!("{out:?}")
    };
    assert_eq!(
        err.to_string(),
        "node 3 (axis 3) configuration step 1 (0x1000:0 device type (CiA 402 servo drive expected)) \
         failed after 1 attempt(s): device type is 0x00040191, expected 0x00020192 (CiA 402 servo drive)"
    );
}

#[test]
fn fake_drive_answers_like_an_sdo_server() {
    let mut drive = FakeDrive::new(5);
    let r = drive.receive(&crate::canopen::sdo::upload_request(
        5,
        ObjectAddr::new(0x1000, 0),
    ));
    assert_eq!(r[0].to_string(), "585#4300100092010200");
    let missing = drive.receive(&crate::canopen::sdo::upload_request(
        5,
        ObjectAddr::new(0x2000, 0),
    ));
    assert_eq!(
        missing[0],
        abort_frame(5, ObjectAddr::new(0x2000, 0), 0x0602_0000, true)
    );
    assert!(decode_response(&missing[0]).is_some());
}
