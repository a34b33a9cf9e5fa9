use super::*;

#[test]
fn the_simulated_bus_has_no_interface_to_wait_for() {
    let config = RobotConfig::prob2_default();
    assert_eq!(config.bus.backend, BusBackend::Sim);
    assert_eq!(interface(&config), None);
}

#[test]
fn socketcan_waits_for_the_configured_interface() {
    let mut config = RobotConfig::prob2_default();
    config.bus.backend = BusBackend::Socketcan;
    config.bus.interface = "vcan0".into();
    assert_eq!(interface(&config), Some("vcan0"));
}
