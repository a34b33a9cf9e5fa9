use super::*;
use proptest::prelude::*;

#[test]
fn pdos_match_the_reference_bytes() {
    // Reference: `185#3702A0860100` (statusword 0x0237, position 100000), here with the
    // profile's current field appended.
    let t = Tpdo1 {
        statusword: 0x0237,
        position: 100_000,
        current_permille: -2,
    };
    assert_eq!(t.encode(5).to_string(), "185#3702A0860100FEFF");
    assert_eq!(Tpdo1::decode(&t.encode(5)), Ok(t));
    // Reference: `205#0F0004870100` (controlword 0x000F, target 100100) plus target torque.
    let r = Rpdo1 {
        controlword: 0x000F,
        target_position: 100_100,
        target_torque: 0x0102,
    };
    assert_eq!(r.encode(5).to_string(), "205#0F00048701000201");
    assert_eq!(Rpdo1::decode(&r.encode(5)), Ok(r));
    let r2 = Rpdo2 {
        mode: 10,
        max_current_permille: 2500,
        torque_offset: -2,
    };
    assert_eq!(r2.encode(3).to_string(), "303#0AC409FEFF");
    assert_eq!(Rpdo2::decode(&r2.encode(3)), Ok(r2));
    let t2 = Tpdo2 { mode_display: 8 };
    assert_eq!(t2.encode(6).to_string(), "286#08");
    assert_eq!(
        Tpdo2::decode(&Frame::new(0x286, &[0xF6]).unwrap()),
        Ok(Tpdo2 { mode_display: -10 })
    );
}

#[test]
fn wrong_lengths_are_named() {
    let short = Frame::new(0x185, &[0x37, 0x02, 0xA0, 0x86, 0x01, 0x00]).unwrap();
    let err = Tpdo1::decode(&short).unwrap_err();
    assert_eq!(
        err.to_string(),
        "TPDO1 from COB-ID 0x185 has 6 data bytes; the MCM drive profile maps exactly 8"
    );
    assert!(Tpdo2::decode(&Frame::new(0x285, &[]).unwrap()).is_err());
    assert!(Rpdo2::decode(&Frame::new(0x305, &[1, 2]).unwrap()).is_err());
}

proptest! {
    #[test]
    fn pdos_round_trip(cw: u16, pos: i32, tq: i16, node in 1u8..=127) {
        let r = Rpdo1 { controlword: cw, target_position: pos, target_torque: tq };
        prop_assert_eq!(Rpdo1::decode(&r.encode(node)), Ok(r));
        let t = Tpdo1 { statusword: cw, position: pos, current_permille: tq };
        prop_assert_eq!(Tpdo1::decode(&t.encode(node)), Ok(t));
    }
}
