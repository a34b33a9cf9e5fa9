use super::*;

#[test]
fn cob_ids_of_the_predefined_connection_set() {
    assert_eq!(emcy_id(3), 0x083);
    assert_eq!(tpdo_id(1, 5), 0x185);
    assert_eq!(tpdo_id(2, 5), 0x285);
    assert_eq!(rpdo_id(1, 5), 0x205);
    assert_eq!(rpdo_id(2, 5), 0x305);
    assert_eq!(sdo_rx_id(5), 0x605);
    assert_eq!(sdo_tx_id(5), 0x585);
    assert_eq!(heartbeat_id(127), 0x77F);
}

#[test]
fn classify_round_trips_every_service() {
    assert_eq!(classify(0x000), Service::Nmt);
    assert_eq!(classify(0x080), Service::Sync);
    assert_eq!(classify(0x100), Service::Time);
    assert_eq!(classify(0x083), Service::Emcy { node: 3 });
    for node in 1..=127u8 {
        assert_eq!(classify(tpdo_id(1, node)), Service::Tpdo { pdo: 1, node });
        assert_eq!(classify(tpdo_id(2, node)), Service::Tpdo { pdo: 2, node });
        assert_eq!(classify(rpdo_id(1, node)), Service::Rpdo { pdo: 1, node });
        assert_eq!(classify(rpdo_id(2, node)), Service::Rpdo { pdo: 2, node });
        assert_eq!(classify(sdo_tx_id(node)), Service::SdoResponse { node });
        assert_eq!(classify(sdo_rx_id(node)), Service::SdoRequest { node });
        assert_eq!(classify(heartbeat_id(node)), Service::Heartbeat { node });
    }
    assert_eq!(classify(0x7E4), Service::Other { id: 0x7E4 });
}

#[test]
fn mapping_entries_match_the_profile() {
    assert_eq!(mapping_entry(CONTROLWORD, 0, 16), 0x6040_0010);
    assert_eq!(mapping_entry(TARGET_POSITION, 0, 32), 0x607A_0020);
    assert_eq!(mapping_entry(MODES_OF_OPERATION, 0, 8), 0x6060_0008);
    assert_eq!(ObjectAddr::new(0x1400, 1).to_string(), "0x1400:1");
}
