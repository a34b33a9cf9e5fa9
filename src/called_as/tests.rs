use super::*;

fn args(words: &[&str]) -> Vec<OsString> {
    words.iter().map(OsString::from).collect()
}

#[test]
fn a_link_named_after_a_program_runs_it() {
    assert_eq!(
        arguments(
            "/usr/bin/mcm-rt".as_ref(),
            args(&["--config", "/etc/mcm/prob2.toml"])
        ),
        args(&["rt", "--config", "/etc/mcm/prob2.toml"])
    );
    assert_eq!(
        arguments("mcm-gateway".as_ref(), args(&["--version"])),
        args(&["gateway", "--version"])
    );
    assert_eq!(
        arguments("/usr/bin/mcm-ros2".as_ref(), args(&[])),
        args(&["ros2"])
    );
    assert_eq!(
        arguments(
            "/usr/bin/mcm-virtual-arm".as_ref(),
            args(&["--interface", "vcan0"])
        ),
        args(&["virtual-arm", "--interface", "vcan0"])
    );
}

#[test]
fn the_launchers_children_keep_their_subcommand_once() {
    // argv[0] `mcm-rt`, then `rt ...`: as the launcher starts them.
    assert_eq!(
        arguments("mcm-rt".as_ref(), args(&["rt", "--instance", "x"])),
        args(&["rt", "--instance", "x"])
    );
}

#[test]
fn mcm_by_its_own_name_is_the_launcher() {
    for program in ["mcm", "/usr/bin/mcm", "target/debug/mcm", "mcm-other"] {
        assert_eq!(
            arguments(program.as_ref(), args(&["--instance", "x"])),
            args(&["--instance", "x"]),
            "{program}"
        );
    }
}
