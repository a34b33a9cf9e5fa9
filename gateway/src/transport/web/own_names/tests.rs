use super::*;

fn names() -> OwnNames {
    let configured = vec![
        HostName::parse("robot-7.cell.example").unwrap(),
        HostName::parse("10.17.0.5").unwrap(),
    ];
    OwnNames::new(configured, "192.0.2.44".parse().unwrap())
}

fn check(host: Option<&str>, uri: &str) -> Result<(), Refusal> {
    let mut headers = HeaderMap::new();
    if let Some(h) = host {
        headers.insert(header::HOST, h.parse().unwrap());
    }
    names().check(&headers, &uri.parse().unwrap())
}

#[test]
fn the_robots_names_are_served_with_or_without_a_port() {
    for host in [
        "localhost",
        "LOCALHOST:18014",
        "127.0.0.1:18014",
        "127.3.0.1",
        "[::1]:18014",
        "[::1]",
        "robot-7.cell.example",
        "Robot-7.Cell.Example.:80",
        "10.17.0.5:18014",
        "192.0.2.44:18014",
    ] {
        assert_eq!(check(Some(host), "/"), Ok(()), "{host}");
    }
}

#[test]
fn another_name_is_refused_naming_it_and_the_setting() {
    for host in [
        "evil.example:18014",
        "evil.example",
        "localhost.evil.example",
        "robot-7.cell.example.evil.example",
        "203.0.113.9:18014",
        "0.0.0.0:18014",
    ] {
        let e = check(Some(host), "/").unwrap_err();
        assert_eq!(e, Refusal::Foreign(host.into()));
        let text = e.to_string();
        assert!(
            text.contains(host) && text.contains("[gateway.web] allowed_hosts"),
            "{text}"
        );
    }
    assert_eq!(check(None, "/"), Err(Refusal::NoHost));
    assert!(
        check(None, "/")
            .unwrap_err()
            .to_string()
            .contains("allowed_hosts")
    );
    assert!(matches!(
        check(Some("::1"), "/"),
        Err(Refusal::Unreadable { .. })
    ));
}

#[test]
fn a_request_in_absolute_form_is_checked_by_its_target_too() {
    assert_eq!(check(Some("localhost"), "http://localhost:18014/"), Ok(()));
    assert_eq!(
        check(Some("localhost"), "http://evil.example:18014/api/model"),
        Err(Refusal::Foreign("evil.example:18014".into()))
    );
}

#[test]
fn the_machines_own_addresses_are_its_names() {
    let local = local_addresses();
    assert!(
        local.contains(&"127.0.0.1".parse().unwrap()),
        "loopback is an interface address: {local:?}"
    );
    let any = OwnNames::new(vec![], "0.0.0.0".parse().unwrap());
    for a in local {
        assert!(any.is_own(&HostName::Addr(a)), "{a}");
    }
}
