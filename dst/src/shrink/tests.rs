use super::*;

#[test]
fn each_invariant_is_named_by_its_own_words() {
    let calibrate_ok = "calibrate (ALL) of client 2 request 9 answered OK in HOLD, but axis 3 is not flagged calibrated (axis flags [..])";
    assert_eq!(invariant_of(calibrate_ok), "answered OK");
    let off = "axis 5: flagged calibrated, but measured 1.0 deg vs true 3.0 deg: off by 2.0 deg";
    assert_eq!(invariant_of(off), "flagged calibrated");
    let unknown = "client 2 request 3 of unknown kind 99 answered OK";
    assert_eq!(invariant_of(unknown), "of unknown kind");
    // The refusals' words, before those they may quote.
    let refused = "move_axis refused as axis 3 not calibrated, but it was flagged calibrated before the cycle and after it";
    assert_eq!(invariant_of(refused), "refused as axis");
    let went = "move_axis refused (target 200.000 deg beyond the software limits), but the mode went from HOLD to PVT";
    assert_eq!(invariant_of(went), "but the mode went from");
    let left = "2 commands left unanswered at the end of the run";
    assert_eq!(invariant_of(left), "another invariant");
}
