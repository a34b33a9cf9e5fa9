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
