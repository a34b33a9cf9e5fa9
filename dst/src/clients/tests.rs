use super::*;
use mcm_shared::mode::CommandKind;

#[test]
fn most_garbage_samples_of_a_known_kind_get_past_their_flags_to_the_arguments() {
    let mut rng = Rng::new(3);
    let mut client = Client::new(FIRST_CLIENT_ID, &mut rng);
    let (mut known, mut refused_on_flags) = (0, 0);
    for _ in 0..2_000 {
        let c = client.garbage(&mut rng);
        if CommandKind::try_from(c.kind).is_err() {
            continue;
        }
        known += 1;
        if let Err(e) = Request::decode(&c)
            && e.to_string().contains(": flags =")
        {
            refused_on_flags += 1;
        }
    }
    assert!(known > 1_000, "{known} samples of a known kind");
    assert!(
        refused_on_flags * 5 < known,
        "{refused_on_flags} of {known} refused on their flags"
    );
    assert!(refused_on_flags > 0, "random flags are tried too");
}

/// Every command kind is sent in a run: the clients' random draws send each kind
/// [`requests::Sender`] gives them, the fault injector sends its kinds, a disconnecting client
/// its own. A kind that nobody sends (a new command whose arguments are never drawn) fails here.
#[test]
fn every_command_kind_is_sent_in_a_run() {
    use crate::faults::{Fault, Schedule};
    use requests::Sender;
    use std::collections::HashSet;

    let cfg = RobotConfig::prob2_default();
    let lim = Limits::of(&cfg);
    let state = StateSample::default();
    let mut rng = Rng::new(7);
    let mut client = Client::new(FIRST_CLIENT_ID, &mut rng);
    let kind_of = |c: &CommandSample| Request::decode(c).expect("a request decodes").kind();

    let mut drawn = HashSet::new();
    for _ in 0..5_000 {
        if let Draw::Kind(kind) = draw(&mut rng) {
            let r = client.random_request(kind, &state, &lim, &mut rng);
            assert_eq!(r.map(|r| r.kind()), Some(kind), "a draw of {kind}");
            drawn.insert(kind);
        }
    }
    let mut injected = HashSet::new();
    let mut faults = Schedule::new([Some(0.05); Fault::ALL.len()], &cfg, 1);
    for k in 0..20_000 {
        injected.extend(faults.tick(k, &mut rng).commands.iter().map(kind_of));
    }
    let gone = kind_of(&client.gone());

    for kind in CommandKind::ALL {
        let sent = match Sender::of(*kind) {
            Sender::Clients => drawn.contains(kind),
            Sender::FaultInjector => injected.contains(kind),
            Sender::Disconnecting => gone == *kind,
        };
        assert!(
            sent,
            "{kind} ({:?}) is never sent in a run",
            Sender::of(*kind)
        );
    }
}
