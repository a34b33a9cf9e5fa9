use super::*;

#[test]
fn names_parse_back() {
    for d in RosDistro::ALL {
        assert_eq!(RosDistro::parse(d.name()), Ok(d));
    }
}

#[test]
fn an_unknown_name_is_refused_naming_it_and_the_allowed_ones() {
    let e = RosDistro::parse("rolling").unwrap_err().to_string();
    assert_eq!(
        e,
        "ROS 2 distribution \"rolling\" is not served by this build; allowed: jazzy, \
         kilted, lyrical"
    );
    let e = RosDistro::parse("humble").unwrap_err().to_string();
    assert!(
        e.contains("\"humble\"") && e.contains("24-byte GUIDs"),
        "{e}"
    );
}

#[test]
fn the_default_is_ros_distro_when_known_else_jazzy() {
    assert_eq!(RosDistro::from_env(None), (RosDistro::Jazzy, None));
    assert_eq!(RosDistro::from_env(Some("")), (RosDistro::Jazzy, None));
    assert_eq!(
        RosDistro::from_env(Some("kilted")),
        (RosDistro::Kilted, None)
    );
    assert_eq!(
        RosDistro::from_env(Some("lyrical")),
        (RosDistro::Lyrical, None)
    );
    let (d, why) = RosDistro::from_env(Some("humble"));
    assert_eq!(d, RosDistro::Jazzy);
    assert_eq!(why.expect("a reason").value, "humble");
}

#[test]
fn only_control_msgs_6_has_the_feedback_index() {
    assert!(!RosDistro::Jazzy.feedback_has_index());
    assert!(RosDistro::Kilted.feedback_has_index());
    assert!(RosDistro::Lyrical.feedback_has_index());
}
