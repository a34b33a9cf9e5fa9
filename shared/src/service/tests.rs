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

/// Every instance name `ServiceNames::new` accepts makes service names iceoryx2 accepts: the
/// shortest and the longest, and every character allowed.
#[test]
fn every_service_name_of_an_instance_is_an_iceoryx2_name() {
    let alphabet: String = ('a'..='z')
        .chain('A'..='Z')
        .chain('0'..='9')
        .chain(['-', '_'])
        .collect();
    let mut instances = vec!["x".to_string(), "x".repeat(MAX_INSTANCE)];
    instances.extend(
        alphabet
            .as_bytes()
            .chunks(MAX_INSTANCE)
            .map(|c| String::from_utf8(c.to_vec()).unwrap()),
    );
    for c in alphabet.chars() {
        instances.push(c.to_string());
        instances.push(c.to_string().repeat(MAX_INSTANCE));
    }
    for instance in instances {
        let n = ServiceNames::new(&instance).unwrap();
        let pairs = [
            (n.state_service(), n.state()),
            (n.state_event_service(), n.state_event()),
            (n.command_service(), n.command()),
        ];
        for (service, name) in pairs {
            assert_eq!(service.as_str(), name);
        }
    }
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
