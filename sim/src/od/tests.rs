use super::*;

fn od() -> Od {
    Od::new(&OdDefaults {
        node_id: 3,
        rated_current_ma: 4000,
        rated_torque_mnm: 480,
        peak_current_permille: 2500,
    })
}

#[test]
fn table_is_sorted_and_unique() {
    for w in TABLE.windows(2) {
        assert!(
            (w[0].index, w[0].sub) < (w[1].index, w[1].sub),
            "{:?} !< {:?}",
            w[0],
            w[1]
        );
    }
}

#[test]
fn defaults_depend_on_node_and_motor() {
    let od = od();
    assert_eq!(od.raw(RPDO_COMM[1].cob_id), 0x8000_0303);
    assert_eq!(od.raw(TPDO_COMM[0].cob_id), 0x8000_0183);
    assert_eq!(od.raw(RATED_CURRENT), 4000);
    assert_eq!(od.raw(RATED_TORQUE), 480);
    assert_eq!(od.raw(MAX_CURRENT), 2500);
    assert_eq!(od.i32(INTERPOLATION_INDEX), -3);
}

#[test]
fn lookup_distinguishes_missing_object_and_sub() {
    assert_eq!(Od::lookup(0x6041, 0), Ok(STATUSWORD));
    assert_eq!(
        Od::lookup(0x2000, 0),
        Err(SdoAbort::ObjectDoesNotExist { index: 0x2000 })
    );
    assert_eq!(
        Od::lookup(0x1600, 9),
        Err(SdoAbort::SubIndexDoesNotExist {
            index: 0x1600,
            sub: 9
        })
    );
}

#[test]
fn signed_values_round_trip() {
    let mut od = od();
    od.set_i32(TARGET_TORQUE, -1234);
    assert_eq!(od.raw(TARGET_TORQUE), 0xFB2E);
    assert_eq!(od.i32(TARGET_TORQUE), -1234);
    od.set_i32(POSITION_ACTUAL, i32::MIN);
    assert_eq!(od.i32(POSITION_ACTUAL), i32::MIN);
}

#[test]
fn stored_calibration_survives_both_resets() {
    let mut od = od();
    assert_eq!(
        (od.i32(CALIBRATION_OFFSET), od.raw(CALIBRATION_VALID)),
        (0, 0)
    );
    assert_eq!(Od::def(CALIBRATION_OFFSET).mappable, Mappable::No);
    assert_eq!(Od::def(CALIBRATION_VALID).access, Access::Rw);
    od.set_i32(CALIBRATION_OFFSET, -123_456);
    od.set_raw(CALIBRATION_VALID, 1);
    od.reset_application();
    od.reset_communication();
    assert_eq!(
        (od.i32(CALIBRATION_OFFSET), od.raw(CALIBRATION_VALID)),
        (-123_456, 1)
    );
}

#[test]
fn resets_touch_only_their_range() {
    let mut od = od();
    od.set_raw(PRODUCER_HEARTBEAT, 50);
    od.set_raw(MODES_OF_OPERATION, 8);
    od.reset_application();
    assert_eq!(
        (od.raw(PRODUCER_HEARTBEAT), od.raw(MODES_OF_OPERATION)),
        (50, 0)
    );
    od.set_raw(MODES_OF_OPERATION, 8);
    od.reset_communication();
    assert_eq!(
        (od.raw(PRODUCER_HEARTBEAT), od.raw(MODES_OF_OPERATION)),
        (0, 8)
    );
}
