//! The access decisions as pure functions: networks, the secret, `sim` from loopback.

use super::*;

fn ip(s: &str) -> IpAddr {
    s.parse().unwrap()
}

fn nets(list: &[&str]) -> Option<Vec<Cidr>> {
    Some(list.iter().map(|s| Cidr::parse(s).unwrap()).collect())
}

#[test]
fn by_default_everything_is_allowed_but_remote_sim() {
    let a = Access::default();
    for peer in ["10.1.2.3", "127.0.0.1", "2001:db8::7", "::1"] {
        assert_eq!(a.decide(Need::Motion, ip(peer), false), Ok(()), "{peer}");
        assert_eq!(a.decide(Need::Open, ip(peer), false), Ok(()), "{peer}");
    }
    assert_eq!(a.decide(Need::Sim, ip("127.0.0.1"), false), Ok(()));
    assert_eq!(a.decide(Need::Sim, ip("::1"), false), Ok(()));
    assert_eq!(a.decide(Need::Sim, ip("::ffff:127.0.0.1"), false), Ok(()));
    assert_eq!(
        a.decide(Need::Sim, ip("10.1.2.3"), false),
        Err(Refusal::RemoteSim)
    );
    let remote = Access::new(None, None, true);
    assert_eq!(remote.decide(Need::Sim, ip("10.1.2.3"), false), Ok(()));
}

#[test]
fn motion_only_from_the_allowed_networks_and_hold_from_anywhere() {
    let a = Access::new(nets(&["10.17.0.0/16", "fd00::/8"]), None, false);
    assert_eq!(a.decide(Need::Motion, ip("10.17.3.4"), false), Ok(()));
    assert_eq!(
        a.decide(Need::Motion, ip("::ffff:10.17.3.4"), false),
        Ok(())
    );
    assert_eq!(a.decide(Need::Motion, ip("fd00::1"), false), Ok(()));
    for outside in ["10.18.0.1", "127.0.0.1", "2001:db8::1"] {
        assert_eq!(
            a.decide(Need::Motion, ip(outside), false),
            Err(Refusal::Network),
            "{outside}"
        );
        assert_eq!(
            a.decide(Need::Open, ip(outside), false),
            Ok(()),
            "{outside}"
        );
    }
    let text = a.refusal_text("move_axis", Refusal::Network, ip("10.18.0.1"));
    assert!(
        text.contains("10.18.0.1") && text.contains("10.17.0.0/16, fd00::/8"),
        "{text}"
    );
    assert!(
        text.contains("motion_networks") && text.contains("`hold`"),
        "{text}"
    );
}

#[test]
fn with_a_secret_motion_needs_authentication_and_only_the_right_secret_matches() {
    let hash = sha256::digest(b"correct horse");
    let a = Access::new(None, Some(hash), false);
    assert_eq!(
        a.decide(Need::Motion, ip("10.1.2.3"), false),
        Err(Refusal::NotAuthenticated)
    );
    assert_eq!(a.decide(Need::Motion, ip("10.1.2.3"), true), Ok(()));
    assert_eq!(a.decide(Need::Open, ip("10.1.2.3"), false), Ok(()));
    assert!(a.secret_matches("correct horse"));
    assert!(!a.secret_matches("correct horse "));
    assert!(!a.secret_matches(""));
    assert!(Access::default().secret_matches("anything"));
    let text = a.refusal_text("take_control", Refusal::NotAuthenticated, ip("10.1.2.3"));
    assert!(text.contains("\"command\":\"authenticate\""), "{text}");
    // A network refusal comes first: the secret does not open a closed network.
    let both = Access::new(nets(&["10.0.0.0/8"]), Some(hash), false);
    assert_eq!(
        both.decide(Need::Motion, ip("192.168.1.1"), true),
        Err(Refusal::Network)
    );
}

#[test]
fn the_secret_file_holds_a_hash_as_sha256sum_prints_it() {
    let dir = std::env::temp_dir().join(format!("mcm-access-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("secret.sha256");
    // `printf '%s' abc | sha256sum`
    std::fs::write(
        &file,
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad  -\n",
    )
    .unwrap();
    let cfg = AccessConfig {
        motion_networks: None,
        secret_sha256_file: Some(file.display().to_string()),
    };
    let a = Access::from_config(&cfg, false).unwrap();
    assert!(a.secret_matches("abc") && !a.secret_matches("abd"));
    std::fs::write(&file, "not a hash\n").unwrap();
    let e = Access::from_config(&cfg, false).unwrap_err().to_string();
    assert!(
        e.contains("64 hex digits") && e.contains("sha256sum"),
        "{e}"
    );
    let missing = AccessConfig {
        secret_sha256_file: Some(dir.join("nope").display().to_string()),
        ..cfg
    };
    let e = Access::from_config(&missing, false)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("secret_sha256_file") && e.contains("nope"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn what_each_command_needs() {
    let cfg = mcm_shared::config::RobotConfig::prob2_default();
    let parse = |s: &str| Command::from_json(s, &cfg).unwrap();
    assert_eq!(need(&parse(r#"{"command":"hold"}"#)), Need::Open);
    assert_eq!(need(&parse(r#"{"command":"status"}"#)), Need::Open);
    assert_eq!(need(&parse(r#"{"command":"release_control"}"#)), Need::Open);
    assert_eq!(need(&parse(r#"{"command":"take_control"}"#)), Need::Motion);
    assert_eq!(need(&parse(r#"{"command":"release"}"#)), Need::Motion);
    assert_eq!(
        need(&parse(
            r#"{"command":"move_axis","arguments":{"axis_index":1,"target_position":0}}"#
        )),
        Need::Motion
    );
    assert_eq!(
        need(&parse(
            r#"{"command":"sim","arguments":{"emergency_stop":false}}"#
        )),
        Need::Sim
    );
    // Executed by the gateway: a pose to move to is motion, a pose to solve is not.
    let pose = r#""position":[0.4,0,0.5],"orientation":[0,0,0,1]"#;
    assert_eq!(
        need(&parse(&format!(
            r#"{{"command":"move_to_pose","arguments":{{{pose}}}}}"#
        ))),
        Need::Motion
    );
    assert_eq!(
        need(&parse(&format!(
            r#"{{"command":"inverse_kinematics","arguments":{{{pose}}}}}"#
        ))),
        Need::Open
    );
}

#[test]
fn refusals_are_counted_by_reason() {
    let a = Access::default();
    a.count(Refusal::Network);
    a.count(Refusal::Network);
    a.count(Refusal::NotOwner);
    assert_eq!(a.refused(Refusal::Network), 2);
    assert_eq!(a.refused(Refusal::NotOwner), 1);
    assert_eq!(a.refused(Refusal::WrongSecret), 0);
}
