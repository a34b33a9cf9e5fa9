use super::*;
use crate::od::{OdDefaults, slot};

fn od() -> Od {
    Od::new(&OdDefaults {
        node_id: 2,
        rated_current_ma: 4000,
        rated_torque_mnm: 480,
        peak_current_permille: 2500,
    })
}

/// Write through the checks, like the SDO server does.
fn w(od: &mut Od, op: bool, index: u16, sub: u8, v: u32) -> Result<(), SdoAbort> {
    let s = Od::lookup(index, sub)?;
    check_write(od, op, s, v)?;
    od.set_raw(s, v);
    Ok(())
}

fn configure_rpdo1(od: &mut Od, trans: u32) {
    for (i, s, v) in [
        (0x1400, 1, 0x8000_0202),
        (0x1600, 0, 0),
        (0x1600, 1, 0x6040_0010),
        (0x1600, 2, 0x607A_0020),
        (0x1600, 3, 0x6071_0010),
        (0x1600, 0, 3),
        (0x1400, 2, trans),
        (0x1400, 1, 0x0000_0202),
    ] {
        w(od, false, i, s, v).unwrap();
    }
}

#[test]
fn mapping_rules_and_abort_codes() {
    let mut od = od();
    // valid PDO: mapping refused
    w(&mut od, false, 0x1400, 1, 0x202).unwrap();
    assert_eq!(
        w(&mut od, false, 0x1600, 0, 0).unwrap_err().code(),
        0x0800_0022
    );
    w(&mut od, false, 0x1400, 1, 0x8000_0202).unwrap();
    // OPERATIONAL: refused even while invalid
    assert_eq!(
        w(&mut od, true, 0x1600, 1, 0x6040_0010).unwrap_err().code(),
        0x0800_0022
    );
    // wrong direction, wrong length, missing object, not mappable
    for entry in [0x6041_0010, 0x6040_0020, 0x2000_0010, 0x6075_0020] {
        assert_eq!(
            w(&mut od, false, 0x1600, 1, entry).unwrap_err().code(),
            0x0604_0041,
            "{entry:08X}"
        );
    }
    // 3 x 32 bits = 96 > 64
    for k in 1..=3 {
        w(&mut od, false, 0x1600, k, 0x607A_0020).unwrap();
    }
    assert_eq!(
        w(&mut od, false, 0x1600, 0, 3).unwrap_err().code(),
        0x0604_0042
    );
    assert_eq!(
        w(&mut od, false, 0x1600, 0, 9).unwrap_err().code(),
        0x0609_0030
    );
    w(&mut od, false, 0x1600, 0, 2).unwrap();
    // entries only while the count is 0
    assert_eq!(
        w(&mut od, false, 0x1600, 1, 0x6040_0010)
            .unwrap_err()
            .code(),
        0x0800_0022
    );
    // TPDO mapping takes transmit objects only
    assert_eq!(
        w(&mut od, false, 0x1A00, 1, 0x6040_0010)
            .unwrap_err()
            .code(),
        0x0604_0041
    );
    w(&mut od, false, 0x1A00, 1, 0x6041_0010).unwrap();
}

#[test]
fn comm_parameter_rules() {
    let mut od = od();
    for t in [0, 241, 252, 253] {
        assert_eq!(
            w(&mut od, false, 0x1400, 2, t).unwrap_err().code(),
            0x0609_0030,
            "type {t}"
        );
    }
    for t in [1, 240, 254, 255] {
        w(&mut od, false, 0x1400, 2, t).unwrap();
    }
    assert_eq!(
        w(&mut od, false, 0x1400, 1, 0x2000_0202)
            .unwrap_err()
            .code(),
        0x0609_0030,
        "29-bit"
    );
    w(&mut od, false, 0x1400, 1, 0x202).unwrap();
    assert_eq!(
        w(&mut od, false, 0x1400, 1, 0x203).unwrap_err().code(),
        0x0609_0030,
        "id change while valid"
    );
    w(&mut od, false, 0x1400, 1, 0x8000_0203).unwrap();
}

#[test]
fn sync_rpdo_is_latched_until_sync_and_event_rpdo_applies_now() {
    let mut od = od();
    configure_rpdo1(&mut od, 1);
    let mut e = PdoEngine::default();
    e.start();
    let f = Frame::new(0x202, &[0x0F, 0x00, 0x10, 0x27, 0x00, 0x00, 0x9C, 0xFF]).unwrap();
    assert_eq!(e.on_frame(&od, &f), RxOutcome::Latched);
    let g = Frame::new(0x202, &[0x06, 0x00, 0x20, 0x4E, 0x00, 0x00, 0x00, 0x00]).unwrap();
    assert_eq!(
        e.on_frame(&od, &g),
        RxOutcome::Latched,
        "the newest one wins"
    );
    let [first, second] = e.take_latched(&od);
    let writes: Vec<_> = first.unwrap().iter().collect();
    assert_eq!(
        writes,
        [
            (od::CONTROLWORD, 0x06),
            (od::TARGET_POSITION, 20000),
            (od::TARGET_TORQUE, 0)
        ]
    );
    assert_eq!(second, None);
    assert_eq!(e.take_latched(&od), [None, None], "applied once");
    assert_eq!(
        e.on_frame(&od, &Frame::new(0x202, &[0x0F, 0]).unwrap()),
        RxOutcome::TooShort
    );
    assert_eq!(
        e.on_frame(&od, &Frame::new(0x302, &[0; 8]).unwrap()),
        RxOutcome::NotMine,
        "RPDO2 invalid"
    );

    let mut od = self::od();
    configure_rpdo1(&mut od, 255);
    let RxOutcome::Apply(writes) = e.on_frame(&od, &f) else {
        panic!()
    };
    assert_eq!(writes.iter().nth(2), Some((od::TARGET_TORQUE, 0xFF9C)));
}

#[test]
fn tpdos_sync_every_nth_and_events_on_change() {
    let mut od = od();
    for (i, s, v) in [
        (0x1A00, 1, 0x6041_0010),
        (0x1A00, 2, 0x6064_0020),
        (0x1A00, 0, 2),
        (0x1800, 2, 2),
        (0x1800, 1, 0x182),
    ] {
        w(&mut od, false, i, s, v).unwrap();
    }
    for (i, s, v) in [
        (0x1A01, 1, 0x6061_0008),
        (0x1A01, 0, 1),
        (0x1801, 2, 255),
        (0x1801, 1, 0x282),
    ] {
        w(&mut od, false, i, s, v).unwrap();
    }
    od.set_raw(od::STATUSWORD, 0x0237);
    od.set_i32(od::POSITION_ACTUAL, -2);
    let mut e = PdoEngine::default();
    e.start();
    let sent: Vec<bool> = (0..4).map(|_| e.sync_tx(&od)[0].is_some()).collect();
    assert_eq!(sent, [false, true, false, true], "type 2: every 2nd SYNC");
    assert_eq!(e.sync_tx(&od)[0], None);
    assert_eq!(e.sync_tx(&od)[0].unwrap().to_string(), "182#3702FEFFFFFF");
    assert_eq!(
        e.event_tx(&od, 0)[1].unwrap().to_string(),
        "282#00",
        "once on start"
    );
    assert_eq!(e.event_tx(&od, 0), [None, None]);
    od.set_i32(od::MODES_DISPLAY, 8);
    assert_eq!(e.event_tx(&od, 0)[1].unwrap().to_string(), "282#08");
    assert_eq!(e.event_tx(&od, 0), [None, None]);
    w(&mut od, false, 0x1801, 1, 0x8000_0282).unwrap();
    od.set_i32(od::MODES_DISPLAY, 10);
    assert_eq!(
        e.event_tx(&od, 0),
        [None, None],
        "invalid PDO sends nothing"
    );
    let _ = slot(0x1A01, 8);
}

#[test]
fn an_event_driven_tpdo_is_repeated_when_its_event_timer_runs_out() {
    const MS: u64 = 1_000_000;
    let mut od = od();
    for (i, s, v) in [
        (0x1A01, 1, 0x6061_0008),
        (0x1A01, 0, 1),
        (0x1801, 2, 255),
        (0x1801, 5, 100),
        (0x1801, 1, 0x282),
    ] {
        w(&mut od, false, i, s, v).unwrap();
    }
    od.set_i32(od::MODES_DISPLAY, 8);
    let mut e = PdoEngine::default();
    e.start();
    // The drive's clock at SYNC, every 5 ms: once on start, then every 100 ms.
    let sent_at = |e: &mut PdoEngine, od: &Od, from: u64, to: u64| -> Vec<u64> {
        (from..to)
            .filter(|k| e.event_tx(od, k * 5 * MS)[1].is_some())
            .map(|k| k * 5)
            .collect()
    };
    assert_eq!(sent_at(&mut e, &od, 0, 50), [0, 100, 200]);
    // A change is sent at once and restarts the timer.
    od.set_i32(od::MODES_DISPLAY, 10);
    assert_eq!(e.event_tx(&od, 205 * MS)[1].unwrap().to_string(), "282#0A");
    assert_eq!(sent_at(&mut e, &od, 42, 70), [305]);
    // Event timer 0: only changes.
    w(&mut od, false, 0x1801, 5, 0).unwrap();
    assert_eq!(sent_at(&mut e, &od, 70, 200), Vec::<u64>::new());
}
