use super::*;
use mcm_shared::config::RobotConfig;

const DT: f64 = 0.005;

fn params() -> SafetyParams {
    SafetyParams::from_config(&RobotConfig::prob2_default())
}

fn run(i2t: &mut I2t, current: [f64; 6], seconds: f64) {
    for _ in 0..(seconds / DT).round() as usize {
        i2t.update(&current, DT);
    }
}

#[test]
fn rated_current_converges_to_one_without_derating() {
    let p = params();
    let mut i2t = I2t::new(&p);
    let tau = p.i2t_tau[0];
    run(&mut i2t, p.rated_current, 5.0 * tau);
    for (i, l) in i2t.level().into_iter().enumerate() {
        // 1 - e^-5 = 0.99326
        assert!((l - (1.0 - (-5.0f64).exp())).abs() < 1e-9, "axis {i}: {l}");
    }
    run(&mut i2t, p.rated_current.map(|c| -c), 10.0 * tau); // sign does not matter
    for l in i2t.level() {
        assert!((l - 1.0).abs() < 1e-6 && l <= 1.0, "{l}");
    }
    assert_eq!(i2t.derated(), [false; 6]);
    assert_eq!(i2t.max_current(), p.max_current);
}

#[test]
fn higher_current_derates_at_the_predicted_time_on_that_axis_only() {
    let p = params();
    for axis in 0..6 {
        let mut i2t = I2t::new(&p);
        let mut current = [0.0; 6];
        current[axis] = 1.5 * p.rated_current[axis];
        // level(t) = 2.25 (1 - e^(-t/tau)) crosses 1.0 at t = -tau ln(1 - 1/2.25).
        let t_cross = -p.i2t_tau[axis] * (1.0 - 1.0 / 2.25f64).ln();
        run(&mut i2t, current, t_cross - 0.1);
        assert!(!i2t.derated()[axis], "axis {axis} derated too early");
        run(&mut i2t, current, 0.2);
        let derated = i2t.derated();
        assert!(derated[axis], "axis {axis} not derated");
        assert_eq!(derated.iter().filter(|d| **d).count(), 1);
        let mut expected = p.max_current;
        expected[axis] = p.derated_current[axis];
        assert_eq!(i2t.max_current(), expected);
    }
}

#[test]
fn derating_releases_with_hysteresis() {
    let p = params();
    let mut i2t = I2t::new(&p);
    run(&mut i2t, p.max_current, 60.0);
    assert_eq!(i2t.derated(), [true; 6]);
    // Cool down: still derated between 0.9 and 1.0, released below 0.9.
    let mut seen_between = false;
    for _ in 0..(100.0 / DT) as usize {
        i2t.update(&[0.0; 6], DT);
        let l = i2t.level()[0];
        if (I2T_RELEASE_LEVEL..I2T_DERATE_LEVEL).contains(&l) {
            assert!(i2t.derated()[0], "released at {l}");
            seen_between = true;
        } else if l < I2T_RELEASE_LEVEL {
            assert!(!i2t.derated()[0], "still derated at {l}");
        }
    }
    assert!(seen_between);
    assert_eq!(i2t.derated(), [false; 6]);
    // Once released, running at the rated current (level tends to 1.0 from below) does
    // not derate again.
    run(&mut i2t, p.rated_current, 200.0);
    assert_eq!(i2t.derated(), [false; 6]);
}

#[test]
fn zero_current_cools_down_exponentially() {
    let p = params();
    let mut i2t = I2t::new(&p);
    run(&mut i2t, p.max_current, 60.0);
    let l0 = i2t.level();
    run(&mut i2t, [0.0; 6], p.i2t_tau[0]);
    for (l, l0) in i2t.level().into_iter().zip(l0) {
        assert!((l - l0 * (-1.0f64).exp()).abs() < 1e-9 * l0, "{l} vs {l0}");
    }
}

#[test]
fn bad_inputs_keep_the_model_finite_and_conservative() {
    let p = params();
    let mut hot = I2t::new(&p);
    let mut peak = I2t::new(&p);
    for _ in 0..1000 {
        hot.update(
            &[
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::NAN,
                0.0,
                0.0,
            ],
            DT,
        );
        peak.update(
            &[
                p.max_current[0],
                p.max_current[1],
                p.max_current[2],
                p.max_current[3],
                0.0,
                0.0,
            ],
            DT,
        );
    }
    assert_eq!(
        hot.level(),
        peak.level(),
        "non-finite current counts as peak current"
    );
    let mut i2t = I2t::new(&p);
    i2t.update(&[1e300; 6], DT);
    i2t.update(&[0.0; 6], f64::NAN); // settles at the present (zero) current
    assert!(i2t.level().iter().all(|l| l.is_finite()));
    assert_eq!(i2t.level(), [0.0; 6]);
    i2t.update(&[1e300; 6], f64::INFINITY);
    assert_eq!(i2t.level(), [MAX_INPUT_LEVEL; 6]);
    assert_eq!(i2t.derated(), [true; 6]);
    let before = i2t;
    i2t.update(&[0.0; 6], -1.0);
    i2t.update(&[0.0; 6], 0.0);
    assert_eq!(i2t, before, "dt <= 0 changes nothing");
}
