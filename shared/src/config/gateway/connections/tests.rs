use super::*;
use crate::config::RobotConfig;

fn with(section: &str) -> Result<RobotConfig, ConfigError> {
    let text = format!(
        "{}\n[gateway.connections]\n{section}\n",
        crate::config::PROB2_DEFAULT_TOML
    );
    RobotConfig::from_toml_str(&text)
}

#[test]
fn defaults_apply_without_the_section_and_for_missing_keys() {
    let cfg = with("max_per_peer = 8").unwrap();
    let c = &cfg.gateway.connections;
    assert_eq!(c.max_per_peer, 8);
    assert_eq!(c.max_connections, 64);
    assert_eq!(c.idle_timeout_s, 300.0);
    assert_eq!(
        RobotConfig::prob2_default().gateway.connections,
        ConnectionLimits::default()
    );
}

#[test]
fn out_of_range_values_name_key_value_and_range() {
    for (line, key, value, allowed) in [
        ("max_connections = 0", "max_connections", "0", "1 to 4096"),
        (
            "max_per_peer = 65",
            "max_per_peer",
            "65",
            "1 to max_connections (64)",
        ),
        (
            "loopback_reserve = 64",
            "loopback_reserve",
            "64",
            "0 to max_connections - 1 (63)",
        ),
        (
            "idle_timeout_s = 0.5",
            "idle_timeout_s",
            "0.5",
            "1 to 86400 seconds",
        ),
        (
            "line_timeout_s = inf",
            "line_timeout_s",
            "inf",
            "1 to 86400 seconds",
        ),
        (
            "hmi_line_timeout_s = 1e9",
            "hmi_line_timeout_s",
            "1000000000",
            "1 to 86400",
        ),
    ] {
        let msg = with(line).unwrap_err().to_string();
        assert!(
            msg.contains(&format!("`gateway.connections.{key}` = {value} ")),
            "{line}: {msg}"
        );
        assert!(msg.contains(allowed), "{line}: {msg}");
    }
    assert!(matches!(
        with("max_idle = 3"),
        Err(ConfigError::Parse(m)) if m.contains("max_idle")
    ));
}
