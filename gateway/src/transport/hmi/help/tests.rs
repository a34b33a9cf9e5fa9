use super::super::render::strip_ansi;
use super::*;

fn cfg() -> RobotConfig {
    RobotConfig::prob2_default()
}

#[test]
fn overview_lists_every_command_once() {
    let text = strip_ansi(&overview());
    for name in command_names() {
        let n = text
            .lines()
            .filter(|l| l.trim_start().split(' ').next() == Some(name))
            .count();
        assert_eq!(n, 1, "{name}:\n{text}");
    }
    assert!(
        text.contains("  move_axis       move one axis to a target position\n"),
        "{text}"
    );
    for w in ["watch [detail]", "quit, exit", "help [CMD]", "JSON command"] {
        assert!(text.contains(w), "{w}");
    }
}

#[test]
fn command_help_explains_arguments_units_defaults_and_modes() {
    let text = strip_ansi(&topic("move_axis", &cfg()));
    for w in [
        "move_axis - move one axis to a target position",
        "usage:       move_axis <axis_index> <target_position> [velocity_factor]",
        "axis_index (axis)",
        "target angle [deg]",
        "velocity_factor (vf)",
        "default 0.33333",
        "accepted in: PVT (enter PVT mode first: `hold`, then `pvt`)",
        "reply:       OK as soon as the motion starts",
        "  move_axis 1 30 0.5",
        "reachable positions [deg] (the axis limits less the 1 deg safety margin): \
         1 base -169..169, 2 shoulder -119..119",
    ] {
        assert!(text.contains(w), "{w}:\n{text}");
    }
    let text = strip_ansi(&topic("CALIBRATE", &cfg()));
    assert!(text.contains("accepted in: OFF and HOLD"), "{text}");
    assert!(
        text.contains("which") && text.contains("default ALL"),
        "{text}"
    );
    let text = strip_ansi(&topic("set_torques", &cfg()));
    assert!(
        text.contains("peak torque [Nm]: 1 base -129.6..129.6, "),
        "{text}"
    );
    let text = strip_ansi(&topic("set_velocities", &cfg()));
    assert!(
        text.contains("max velocity [deg/s]: 1 base -90..90, 2 shoulder -90..90"),
        "{text}"
    );
    let text = strip_ansi(&topic("status", &cfg()));
    assert!(text.contains("accepted in: every mode\n"), "{text}");
}

#[test]
fn session_topics_and_typos() {
    assert!(topic("watch", &cfg()).contains("refreshed in place"));
    assert!(topic("exit", &cfg()).contains("end the session"));
    assert!(topic("keys", &cfg()).contains("Ctrl-C"));
    assert_eq!(
        topic("stauts", &cfg()),
        "no help for \"stauts\" (did you mean \"status\"?); `help` lists the commands\n"
    );
}

#[test]
fn every_command_has_help() {
    for name in command_names() {
        let text = topic(name, &cfg());
        assert!(
            text.contains("accepted in:") && text.contains("examples:"),
            "{name}"
        );
    }
}

#[test]
fn help_jog_and_movel_explain_the_tcps_words() {
    let text = strip_ansi(&overview());
    for w in [
        "jog AXIS [SPEED]",
        "jog x|y|z|rx|ry|rz [SPEED] [base|tool]",
        "movel X Y Z [ROLL PITCH YAW] [v=MM_S]",
    ] {
        assert!(text.contains(w), "{w}:\n{text}");
    }
    let text = strip_ansi(&topic("jog", &cfg()));
    for w in ["jog z 50 tool", "`f` switches the frame", "at most 1000"] {
        assert!(text.contains(w), "{w}:\n{text}");
    }
    let text = strip_ansi(&topic("movel", &cfg()));
    for w in ["movel 400 0 400 v=100", "its speed v= is in mm/s"] {
        assert!(text.contains(w), "{w}:\n{text}");
    }
}
