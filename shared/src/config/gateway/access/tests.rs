use super::*;

fn ip(s: &str) -> IpAddr {
    s.parse().unwrap()
}

#[test]
fn networks_contain_their_addresses_only() {
    let n = Cidr::parse("10.17.0.0/16").unwrap();
    assert!(n.contains(ip("10.17.200.3")));
    assert!(!n.contains(ip("10.18.0.1")));
    assert!(n.contains(ip("::ffff:10.17.0.9")), "IPv4 seen through IPv6");
    assert!(!n.contains(ip("fd00::1")));
    let all4 = Cidr::parse("0.0.0.0/0").unwrap();
    assert!(all4.contains(ip("203.0.113.7")));
    let one = Cidr::parse("127.0.0.1").unwrap();
    assert!(one.contains(ip("127.0.0.1")) && !one.contains(ip("127.0.0.2")));
    let v6 = Cidr::parse("fd00::/8").unwrap();
    assert!(v6.contains(ip("fd12::5")) && !v6.contains(ip("fe80::1")));
    assert!(Cidr::parse("::/0").unwrap().contains(ip("2001:db8::1")));
    assert_eq!(v6.to_string(), "fd00::/8");
}

#[test]
fn a_bad_network_is_refused_naming_key_value_and_form() {
    for bad in ["10.0.0.0/33", "10.0.0/8", "fd00::/129", "x", "10.0.0.0/-1"] {
        assert!(Cidr::parse(bad).is_err(), "{bad}");
    }
    let cfg = AccessConfig {
        motion_networks: Some(vec!["10.0.0.0/8".into(), "10.0.0.0/40".into()]),
        secret_sha256_file: None,
    };
    let e = cfg.validate().unwrap_err().to_string();
    assert!(e.contains("gateway.access.motion_networks[1]"), "{e}");
    assert!(e.contains("10.0.0.0/40") && e.contains("0 to 32"), "{e}");
    assert_eq!(AccessConfig::default().networks(), Ok(None));
}
