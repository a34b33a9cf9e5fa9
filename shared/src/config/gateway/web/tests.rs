use super::*;
use crate::config::RobotConfig;

fn with(section: &str) -> Result<RobotConfig, ConfigError> {
    let text = format!(
        "{}\n[gateway.web]\n{section}\n",
        crate::config::PROB2_DEFAULT_TOML
    );
    RobotConfig::from_toml_str(&text)
}

#[test]
fn on_by_default_at_30_frames_a_second() {
    let w = RobotConfig::prob2_default().gateway.web;
    assert_eq!(w, WebConfig::default());
    assert!(w.enabled);
    assert_eq!(w.rate_hz, 30);
    let off = with("enabled = false").unwrap();
    assert!(!off.gateway.web.enabled);
    assert_eq!(with("rate_hz = 100").unwrap().gateway.web.rate_hz, 100);
}

#[test]
fn bad_values_name_key_value_and_what_is_allowed() {
    for (line, key, value, allowed) in [
        ("rate_hz = 0", "gateway.web.rate_hz", "0", "1..=100"),
        ("rate_hz = 101", "gateway.web.rate_hz", "101", "1..=100"),
        (
            "max_per_peer = 0",
            "gateway.web.max_per_peer",
            "0",
            "1..=1024",
        ),
    ] {
        let e = with(line).unwrap_err().to_string();
        assert!(
            e.contains(key) && e.contains(value) && e.contains(allowed),
            "{line}: {e}"
        );
    }
    assert!(with("port = 80").unwrap_err().to_string().contains("port"));
}

#[test]
fn allowed_hosts_are_names_or_addresses() {
    let cfg =
        with("allowed_hosts = [\"Robot-7.cell.example\", \"10.17.0.5\", \"[fd00::5]\"]").unwrap();
    assert_eq!(
        cfg.gateway.web.hosts().unwrap(),
        vec![
            HostName::Name("robot-7.cell.example".into()),
            HostName::Addr("10.17.0.5".parse().unwrap()),
            HostName::Addr("fd00::5".parse().unwrap()),
        ]
    );
    assert_eq!(WebConfig::default().hosts(), Ok(vec![]));
    let e = with("allowed_hosts = [\"robot.example\", \"http://robot.example:80\"]")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("gateway.web.allowed_hosts[1]")
            && e.contains("http://robot.example:80")
            && e.contains("without scheme or port"),
        "{e}"
    );
}
