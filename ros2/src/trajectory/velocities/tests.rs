use super::*;

#[test]
fn a_turning_point_and_the_last_knot_stop() {
    let times = [0.0, 1.0, 2.0, 3.0];
    let pos = [[0.0; 6], [1.0; 6], [0.5; 6], [0.7; 6]];
    let v = fill(&times, &pos, &[Some([0.1; 6]), None, None, None]);
    assert_eq!(v[0], [0.1; 6], "the given velocity is kept");
    assert_eq!(v[1], [0.0; 6], "rises then falls: stops at the knot");
    assert_eq!(v[2], [0.0; 6], "falls then rises: stops at the knot");
    assert_eq!(v[3], [0.0; 6], "the last knot stops");
}

#[test]
fn a_monotone_knot_gets_a_velocity_between_its_slopes() {
    let times = [0.0, 1.0, 1.5];
    let pos = [[0.0; 6], [1.0; 6], [2.0; 6]];
    let v = fill(&times, &pos, &[None, None, None])[1][0];
    // Slopes 1 and 2: the weighted harmonic mean lies strictly between them.
    assert!(v > 1.0 && v < 2.0, "{v}");
    // Equal spans and slopes give that slope.
    let v = fill(&[0.0, 1.0, 2.0], &pos, &[None, None, None])[1][0];
    assert!((v - 1.0).abs() < 1e-12, "{v}");
}
