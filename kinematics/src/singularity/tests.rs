use super::*;
use crate::tests::prob2;

#[test]
fn measures_at_known_configurations() {
    let k = prob2();
    let d = f64::to_radians;
    // Upright: every singularity at once.
    let s = k.singularities(&[0.0; N]);
    assert!(
        s.wrist_rad < 1e-12 && s.elbow_rad < 1e-12 && s.shoulder_m < 1e-12,
        "{s:?}"
    );
    assert_eq!(
        s.near(&SingularityMargins::DEFAULT),
        Near {
            wrist: true,
            elbow: true,
            shoulder: true
        }
    );
    // Axis 5 at 30°, the elbow at 90°, the arm reaching out: none.
    let q = [0.0, d(-30.0), d(-90.0), 0.0, d(30.0), 0.0];
    let s = k.singularities(&q);
    assert!((s.wrist_rad - d(30.0)).abs() < 1e-12, "{s:?}");
    assert!((s.elbow_rad - d(90.0)).abs() < 1e-12, "{s:?}");
    assert!(s.shoulder_m > 0.3, "{s:?}");
    assert!(!s.near(&SingularityMargins::DEFAULT).any());
    // Each alone, just inside its margin.
    let s = k.singularities(&[0.0, d(-30.0), d(-90.0), 0.0, d(-4.9), 0.0]);
    assert_eq!(
        s.near(&SingularityMargins::DEFAULT),
        Near {
            wrist: true,
            ..Near::default()
        }
    );
    let s = k.singularities(&[0.0, d(-30.0), d(175.5), 0.0, d(30.0), 0.0]);
    assert!((s.elbow_rad - d(4.5)).abs() < 1e-12, "{s:?}");
}

/// The shoulder measure is the wrist centre's distance from axis 1 (the P-Rob2 has no
/// shoulder offset).
#[test]
fn shoulder_measure_is_the_distance_from_axis_1() {
    let k = prob2();
    let q = [0.7, 0.4, -0.9, 0.3, 0.8, 0.1];
    let c = k.frames(&q).origin[3];
    let s = k.singularities(&q);
    assert!((s.shoulder_m - c.x.hypot(c.y)).abs() < 1e-12);
}
