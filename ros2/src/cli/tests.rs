use super::Cli;
use crate::distro::RosDistro;
use clap::Parser;

fn parse(args: &[&str]) -> Result<Cli, clap::Error> {
    Cli::try_parse_from(std::iter::once("mcm-ros2").chain(args.iter().copied()))
}

#[test]
fn ros_distro_takes_each_served_distribution() {
    for d in RosDistro::ALL {
        let cli = parse(&["--ros-distro", d.name()]).expect("parses");
        assert_eq!(cli.ros_distro, Some(d));
    }
    assert_eq!(parse(&[]).expect("parses").ros_distro, None);
}

#[test]
fn an_unknown_ros_distro_is_refused_naming_it_and_the_allowed_ones() {
    let e = parse(&["--ros-distro", "rolling"])
        .expect_err("refused")
        .to_string();
    assert!(
        e.contains("\"rolling\" is not served by this build; allowed: jazzy, kilted, lyrical"),
        "{e}"
    );
}

#[test]
fn ros2_read_only_is_a_flag_off_by_default() {
    assert!(!parse(&[]).expect("parses").read_only);
    assert!(parse(&["--ros2-read-only"]).expect("parses").read_only);
    let e = parse(&["--ros2-read-only=yes"])
        .expect_err("a flag takes no value")
        .to_string();
    assert!(e.contains("--ros2-read-only"), "{e}");
}
