use super::*;
use mcm_shared::config::RobotConfig;

const EPS: f64 = 1e-9;

fn params() -> SafetyParams {
    SafetyParams::from_config(&RobotConfig::prob2_default())
}

#[test]
fn just_inside_and_outside_the_band_on_each_axis_both_directions() {
    let p = params();
    let cmd = [0.3, -0.2, 1.0, -1.5, 0.7, 2.0];
    for i in 0..6 {
        let band = p.following_band[i];
        for s in [1.0, -1.0] {
            let mut act = cmd;
            act[i] = cmd[i] + s * (band - EPS);
            assert_eq!(check_following_error(&p, &cmd, &act), Ok(()));
            act[i] = cmd[i] + s * (band + EPS);
            let e = check_following_error(&p, &cmd, &act).unwrap_err();
            assert_eq!((e.check, e.axis, e.limit), (Check::FollowingError, i, band));
            assert!((e.value - (band + EPS)).abs() < 1e-12);
        }
    }
    assert_eq!(check_following_error(&p, &cmd, &cmd), Ok(()));
}

#[test]
fn non_finite_positions_trip() {
    let p = params();
    for i in 0..6 {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut x = [0.0; 6];
            x[i] = bad;
            let e = check_following_error(&p, &x, &[0.0; 6]).unwrap_err();
            assert_eq!((e.check, e.axis), (Check::FollowingError, i));
            let e = check_following_error(&p, &[0.0; 6], &x).unwrap_err();
            assert_eq!(e.axis, i);
            // Both sides the same infinity is not "no error".
            assert!(check_following_error(&p, &x, &x).is_err());
        }
    }
}
