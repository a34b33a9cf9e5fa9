use super::*;

#[test]
fn names_derive_from_instance() {
    let n = ServiceNames::new("test-42_a").unwrap();
    assert_eq!(n.state(), "mcm/test-42_a/state");
    assert_eq!(n.command(), "mcm/test-42_a/command");
    assert_eq!(n.state_event(), "mcm/test-42_a/state-ready");
    assert_eq!(n.node("mcm-rt"), "mcm-rt.test-42_a");
    assert_eq!(n.instance(), "test-42_a");
    assert_eq!(n.to_string(), "test-42_a");
}

#[test]
fn every_service_name_of_an_instance_is_an_iceoryx2_name() {
    let n = ServiceNames::new(&"x".repeat(32)).unwrap();
    for name in [n.state(), n.state_event(), n.command()] {
        assert_eq!(service_name(&name).unwrap().as_str(), name);
    }
    let e = service_name("").unwrap_err();
    assert_eq!(e.name, "");
    assert_eq!(e.source, ServiceNameError::InvalidContent);
    assert!(
        e.to_string()
            .starts_with("iceoryx2 refuses the service name ``: "),
        "{e}"
    );
}

#[test]
fn default_and_longest_instance_names_are_accepted() {
    let d = ServiceNames::new(ServiceNames::DEFAULT_INSTANCE).unwrap();
    assert_eq!(d.state(), "mcm/default/state");
    let longest = "x".repeat(32);
    assert_eq!(ServiceNames::new(&longest).unwrap().instance(), longest);
}

#[test]
fn bad_instance_names_are_refused() {
    for bad in ["", "a/b", "with space", "é", &"x".repeat(33)] {
        let err = ServiceNames::new(bad).unwrap_err();
        assert_eq!(err.name, bad);
        assert_eq!(
            err.to_string(),
            format!(
                "instance name {bad:?} is not allowed: use 1 to 32 characters from a-z, \
                 A-Z, 0-9, '-' and '_'"
            ),
        );
    }
}
