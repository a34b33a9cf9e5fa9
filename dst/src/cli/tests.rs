use super::*;

fn args(line: &str) -> Result<Args, ArgError> {
    parse(line.split_whitespace().map(String::from))
}

#[test]
fn the_defaults_and_every_option() {
    assert_eq!(args(""), Ok(Args::default()));
    let a =
        args("--seed 7 --seconds 20 --hours 0.5 --jobs 2 --first-seed 100 --planted-bug braking")
            .unwrap();
    assert_eq!(
        a,
        Args {
            seed: Some(7),
            seconds: 20.0,
            hours: 0.5,
            jobs: 2,
            first_seed: 100,
            planted: Some(PlantedBug::BrakingCheckOff),
            help: false,
            ..Args::default()
        }
    );
    let r = args("--replay x.script --shrink-replays 50").unwrap();
    assert_eq!(
        (r.replay.as_deref(), r.shrink_replays),
        (Some("x.script"), 50)
    );
    assert_eq!(
        args("--seed 3 --replay x.script").unwrap_err().to_string(),
        "--replay \"x.script\": allowed is a script without --seed (a script names its own seed)"
    );
    assert!(args("--shrink-replays 0").is_err());
    assert!(args("--help").unwrap().help);
    assert!(args("--hours 2 --keep-going").unwrap().keep_going);
    assert!(!args("--hours 2").unwrap().keep_going);
}

#[test]
fn a_value_that_would_run_nothing_or_mean_something_else_is_refused_saying_what_is_allowed() {
    for (line, option, allowed) in [
        ("--seconds -1", "--seconds", POSITIVE),
        ("--seconds NaN", "--seconds", POSITIVE),
        ("--seconds 0", "--seconds", POSITIVE),
        ("--hours inf", "--hours", POSITIVE),
        ("--jobs 0", "--jobs", JOBS),
        ("--jobs -2", "--jobs", JOBS),
        ("--seed x", "--seed", SEED),
        ("--first-seed -1", "--first-seed", SEED),
        ("--planted-bug speed", "--planted-bug", PLANTED),
    ] {
        let value = line.split_whitespace().nth(1).unwrap().to_string();
        let e = args(line).unwrap_err();
        assert_eq!(
            e,
            ArgError::Invalid {
                option,
                value: value.clone(),
                allowed
            },
            "{line}"
        );
        let text = e.to_string();
        assert!(text.contains(&value) && text.contains(allowed), "{text}");
    }
    assert_eq!(args("--jobs"), Err(ArgError::Missing { option: "--jobs" }));
    assert_eq!(
        args("--job 2"),
        Err(ArgError::Unknown {
            arg: "--job".into()
        })
    );
}
