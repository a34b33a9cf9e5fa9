use super::*;
use clap::Parser;

#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    common: CommonArgs,
}

#[test]
fn to_args_parses_back_to_the_same_values() {
    for argv in [
        &["x"][..],
        &["x", "--instance", "robot2", "--config", "/etc/mcm/arm.toml"][..],
    ] {
        let a = Cli::parse_from(argv).common;
        let again = Cli::parse_from(std::iter::once("x".into()).chain(a.to_args())).common;
        assert_eq!(again, a);
    }
    assert_eq!(
        Cli::parse_from(["x"]).common.instance,
        ServiceNames::DEFAULT_INSTANCE
    );
}
