//! The systemd units restart as the launcher does: the gateway's unit carries the numbers of
//! `mcm_shared::restart::GATEWAY_RESTART` (the launcher's own back-off), with no start limit
//! that would give up where the launcher keeps going; the core's unit never restarts it, as
//! the launcher never does. Reads the files of `deploy/systemd/`.

use mcm_shared::restart::GATEWAY_RESTART;

/// The `key=value` lines of `section` in the unit file `name`.
fn section(name: &str, section: &str) -> Vec<String> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("deploy/systemd")
        .join(name);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let mut current = String::new();
    let mut lines = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            current = line.to_string();
        } else if current == format!("[{section}]") && !line.is_empty() && !line.starts_with('#') {
            lines.push(line.to_string());
        }
    }
    lines
}

#[test]
fn the_gateway_unit_restarts_with_the_launchers_back_off() {
    let service = section("mcm-gateway.service", "Service");
    assert!(
        service.contains(&"Restart=always".to_string()),
        "{service:#?}"
    );
    for line in GATEWAY_RESTART.systemd_lines() {
        assert!(service.contains(&line), "{line} missing: {service:#?}");
    }
    let keys = ["RestartSec=", "RestartSteps=", "RestartMaxDelaySec="];
    for key in keys {
        let n = service.iter().filter(|l| l.starts_with(key)).count();
        assert_eq!(n, 1, "{key} once: {service:#?}");
    }
    // systemd's default start limit (5 starts in 10 s) would stop restarting a gateway that
    // keeps dying after 0.1 + 0.2 + 0.4 + 0.8 s; the launcher never gives up.
    let unit = section("mcm-gateway.service", "Unit");
    assert!(
        unit.contains(&"StartLimitIntervalSec=0".to_string()),
        "{unit:#?}"
    );
}

#[test]
fn the_core_unit_is_never_restarted() {
    let service = section("mcm-rt.service", "Service");
    assert!(service.contains(&"Restart=no".to_string()), "{service:#?}");
}
