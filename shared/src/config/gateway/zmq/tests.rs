use super::*;
use crate::config::RobotConfig;

fn with(section: &str) -> Result<RobotConfig, ConfigError> {
    let text = format!(
        "{}\n[gateway.zmq]\n{section}\n",
        crate::config::PROB2_DEFAULT_TOML
    );
    RobotConfig::from_toml_str(&text)
}

#[test]
fn off_by_default_with_the_documented_endpoints() {
    let z = RobotConfig::prob2_default().gateway.zmq;
    assert_eq!(z, ZmqConfig::default());
    assert!(!z.enabled);
    assert_eq!(z.router, "tcp://127.0.0.1:18012");
    assert_eq!(z.publish, "tcp://127.0.0.1:18013");
    let on = with("enabled = true\nrouter = \"tcp://*:5555\"").unwrap();
    assert!(on.gateway.zmq.enabled);
    assert_eq!(on.gateway.zmq.router, "tcp://*:5555");
    assert_eq!(on.gateway.zmq.publish, DEFAULT_PUBLISH);
}

#[test]
fn bad_values_name_key_value_and_what_is_allowed() {
    for (line, key, value) in [
        ("router = \"localhost:5\"", "router", "\"localhost:5\""),
        (
            "publish = \"tcp://h:99999\"",
            "publish",
            "\"tcp://h:99999\"",
        ),
        (
            "publish = \"tcp://127.0.0.1:18012\"",
            "publish",
            "\"tcp://127.0.0.1:18012\"",
        ),
        ("max_peers = 0", "max_peers", "0"),
    ] {
        let msg = with(line).unwrap_err().to_string();
        assert!(
            msg.contains(&format!("`gateway.zmq.{key}` = {value} ")),
            "{line}: {msg}"
        );
    }
    let both_any = with("router = \"tcp://127.0.0.1:*\"\npublish = \"tcp://127.0.0.1:*\"");
    assert!(
        both_any.is_ok(),
        "two `*` ports are two free ports: {both_any:?}"
    );
    assert!(endpoint_ok("ipc:///tmp/mcm-cmd"));
    assert!(endpoint_ok("tcp://127.0.0.1:*"));
    assert!(!endpoint_ok("tcp://:5"));
}
