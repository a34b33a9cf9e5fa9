use super::*;
use mcm_shared::config::RobotConfig;

const EPS: f64 = 1e-9;

fn following() -> FollowingError {
    FollowingError::from_config(&RobotConfig::prob2_default())
}

#[test]
fn prob2_bands_in_si() {
    let f = following();
    assert!((f.band[5] - 2f64.to_radians()).abs() < 1e-15);
    assert!(f.band.iter().all(|b| *b > 0.0));
}

#[test]
fn just_inside_and_outside_the_band_on_each_axis_both_directions() {
    let f = following();
    let cmd = [0.3, -0.2, 1.0, -1.5, 0.7, 2.0];
    for i in 0..6 {
        let band = f.band[i];
        for s in [1.0, -1.0] {
            let mut act = cmd;
            act[i] = cmd[i] + s * (band - EPS);
            assert_eq!(f.check(&cmd, &act), Ok(()));
            act[i] = cmd[i] + s * (band + EPS);
            let e = f.check(&cmd, &act).unwrap_err();
            assert_eq!((e.check, e.axis, e.limit), (Check::FollowingError, i, band));
            assert!((e.value - (band + EPS)).abs() < 1e-12);
        }
    }
    assert_eq!(f.check(&cmd, &cmd), Ok(()));
}

#[test]
fn non_finite_positions_trip() {
    let f = following();
    for i in 0..6 {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut x = [0.0; 6];
            x[i] = bad;
            let e = f.check(&x, &[0.0; 6]).unwrap_err();
            assert_eq!((e.check, e.axis), (Check::FollowingError, i));
            let e = f.check(&[0.0; 6], &x).unwrap_err();
            assert_eq!(e.axis, i);
            // Both sides the same infinity is not "no error".
            assert!(f.check(&x, &x).is_err());
        }
    }
}
