use super::*;
use crate::faulty_bus::BusFaults;

#[test]
fn the_text_reads_back_as_written() {
    let mut args = CommandSample::default();
    args.args[0] = 0.1;
    args.args[3] = -1e-300;
    let script = Script {
        seed: 37,
        fault_kinds: 10,
        planted: Some(PlantedBug::BrakingCheckOff),
        events: vec![
            Event {
                cycle: 4,
                input: Input::Command(CommandSample {
                    client_id: 100,
                    request_id: 7,
                    kind: 6,
                    flags: 1,
                    ..args
                }),
            },
            Event {
                cycle: 4,
                input: Input::Bus(BusFaults {
                    lose_tx: 0.01,
                    lose_heartbeats_of: Some(3),
                    sync_stuck: true,
                    rebooting: Some(5),
                    ..BusFaults::default()
                }),
            },
            Event {
                cycle: 9,
                input: Input::Command(CommandSample::default()),
            },
        ],
    };
    let text = script.to_string();
    assert!(
        text.starts_with("mcm-dst script: seed 37, fault kinds 10, planted braking\n"),
        "{text}"
    );
    assert!(
        text.contains("\n9 command 0 0 0 0\n"),
        "trailing zero arguments left out: {text}"
    );
    assert_eq!(text.parse::<Script>(), Ok(script));
}

#[test]
fn a_bad_text_is_refused_naming_the_line() {
    assert!(matches!(
        "seed 3".parse::<Script>(),
        Err(ScriptError::Header(h)) if h == "seed 3"
    ));
    let e = "mcm-dst script: seed 3, fault kinds 12, planted none\n5 command 1 2\n"
        .parse::<Script>()
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "line 2: not `CYCLE command CLIENT REQUEST KIND FLAGS ARGS...` or `CYCLE bus ...` in \"5 command 1 2\""
    );
    let e = "mcm-dst script: seed 3, fault kinds 12, planted none\n5 bus 0 0 0 0 0 - 0 -\n4 bus 0 0 0 0 0 - 0 -\n"
        .parse::<Script>()
        .unwrap_err();
    assert_eq!(
        e,
        ScriptError::Order {
            line: 3,
            cycle: 4,
            before: 5
        }
    );
    assert!(
        "mcm-dst script: seed 3, fault kinds 12, planted gravity\n"
            .parse::<Script>()
            .is_err()
    );
    assert!(
        "mcm-dst script: seed 3, fault kinds 99, planted none\n"
            .parse::<Script>()
            .is_err(),
        "more fault kinds than there are"
    );
}
