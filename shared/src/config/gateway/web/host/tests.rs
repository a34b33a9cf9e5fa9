use super::*;

fn name(s: &str) -> HostName {
    HostName::Name(s.into())
}

fn addr(s: &str) -> HostName {
    HostName::Addr(s.parse().unwrap())
}

#[test]
fn names_and_addresses_are_told_apart_and_normalised() {
    assert_eq!(
        HostName::parse("Robot-7.Cell.example."),
        Ok(name("robot-7.cell.example"))
    );
    assert_eq!(HostName::parse("10.17.0.5"), Ok(addr("10.17.0.5")));
    assert_eq!(HostName::parse("fd00::5"), Ok(addr("fd00::5")));
    assert_eq!(HostName::parse("[fd00::5]"), Ok(addr("fd00::5")));
    assert_eq!(addr("fd00::5").to_string(), "[fd00::5]");
    assert_eq!(name("robot").to_string(), "robot");
}

#[test]
fn what_is_no_host_says_why() {
    for bad in [
        "",
        ".",
        "robot..example",
        "http://robot",
        "robot:8080",
        "*.example",
        "[10.0.0.1]",
        "a b",
    ] {
        assert!(HostName::parse(bad).is_err(), "{bad:?}");
    }
    let long = format!("{}.example", "a".repeat(64));
    assert!(HostName::parse(&long).unwrap_err().contains("DNS label"));
}

#[test]
fn a_host_header_is_read_with_or_without_its_port() {
    for (header, want) in [
        ("robot.example", name("robot.example")),
        ("ROBOT.example:18014", name("robot.example")),
        ("127.0.0.1:18014", addr("127.0.0.1")),
        ("[::1]", addr("::1")),
        ("[::1]:18014", addr("::1")),
        ("localhost:1", name("localhost")),
    ] {
        assert_eq!(HostName::from_authority(header), Ok(want), "{header}");
    }
    for bad in [
        "::1",
        "[::1",
        "[::1]x",
        "robot:",
        "robot:99999",
        "robot:x",
        "",
    ] {
        assert!(HostName::from_authority(bad).is_err(), "{bad:?}");
    }
}

#[test]
fn localhost_and_loopback_addresses_are_loopback() {
    for h in [
        "localhost",
        "127.0.0.1",
        "127.8.9.1",
        "::1",
        "::ffff:127.0.0.1",
    ] {
        assert!(HostName::parse(h).unwrap().is_loopback(), "{h}");
    }
    for h in ["localhost.evil.example", "10.0.0.1", "::", "0.0.0.0"] {
        assert!(!HostName::parse(h).unwrap().is_loopback(), "{h}");
    }
}
