use super::{MAX_GOALS, Rejections};

#[test]
fn a_run_of_rejections_is_told_once_with_the_limit_and_its_end_with_the_count() {
    let mut r = Rejections::default();
    assert_eq!(r.accepted(), None, "nothing rejected yet");
    let first = r.rejected(MAX_GOALS).expect("the first rejection says why");
    assert!(
        first.contains(&format!("holds {MAX_GOALS} goals")),
        "{first}"
    );
    assert!(first.contains(&format!("at most {MAX_GOALS}")), "{first}");
    assert_eq!(
        r.rejected(MAX_GOALS),
        None,
        "the second of a run is not told"
    );
    assert_eq!(r.rejected(MAX_GOALS), None);
    assert_eq!(
        r.accepted().as_deref(),
        Some("accepting goals again after rejecting 3")
    );
    assert_eq!(r.accepted(), None, "told once");
    assert!(r.rejected(MAX_GOALS).is_some(), "a new run is told again");
}
