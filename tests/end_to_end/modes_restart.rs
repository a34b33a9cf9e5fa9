//! End to end: the calibration survives a restart of the MCM while the (simulated) drives keep
//! their power. The launcher is stopped (SIGTERM; mcm-rt saves the simulated robot) and started
//! again with the same instance name; the drives report the calibration they kept.

use crate::common;

use common::{Client, Mcm};
use mcm_shared::service::sim_state_path;
use serde_json::{Value, json};

fn six(v: &Value) -> [f64; 6] {
    let a = v
        .as_array()
        .unwrap_or_else(|| panic!("expected an array of 6 numbers, got {v}"));
    assert_eq!(a.len(), 6, "expected 6 numbers, got {v}");
    std::array::from_fn(|i| a[i].as_f64().unwrap_or_else(|| panic!("not a number: {v}")))
}

fn max_diff(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn assert_ok(v: &Value) {
    assert_eq!(v["result_type"], "generic", "{v}");
    assert_eq!(v["error_status"], "OK", "{v}");
}

fn detail(c: &mut Client) -> Value {
    let s = c.request(r#"{"command":"status","arguments":{"detail":true}}"#);
    assert_eq!(s["result_type"], "status", "{s}");
    s
}

/// The simulation's true joint angles and velocities [deg, deg/s].
fn truth(c: &mut Client) -> ([f64; 6], [f64; 6]) {
    let r = c.request(r#"{"command":"sim"}"#);
    assert_eq!(r["result_type"], "sim", "{r}");
    (six(&r["true_position"]), six(&r["true_velocity"]))
}

/// Hold, wait until the true arm is at rest, then the reported positions must be the true
/// angles.
fn assert_positions_true(c: &mut Client) {
    let r = c.request(r#"{"command":"hold"}"#);
    assert_eq!(r["operating_mode"], "HOLD", "{r}");
    let deadline = std::time::Instant::now() + common::WAIT;
    loop {
        let (_, v) = truth(c);
        if v.iter().all(|x| x.abs() < 0.1) {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "arm not at rest: {v:?}"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let s = detail(c);
    let (t, _) = truth(c);
    let p = six(&s["axis_states"]["position"]);
    assert!(max_diff(&p, &t) < 0.05, "reported {p:?} vs true {t:?}");
}

#[test]
fn calibration_survives_a_restart_of_the_mcm() {
    let mcm = Mcm::start("restart");
    let instance = mcm.instance.clone();
    let mut c = mcm.client();
    c.wait_drives_online();
    assert_ok(&c.request(r#"{"command":"calibrate"}"#));
    assert_positions_true(&mut c);
    drop(c);
    assert!(mcm.stop().success());
    assert!(
        sim_state_path(&instance).exists(),
        "mcm-rt saved the simulated robot"
    );

    let mcm = Mcm::start_named(&instance, &[]);
    assert!(
        !sim_state_path(&instance).exists(),
        "resumed: the saved state is consumed"
    );
    let mut c = mcm.client();
    let s = c.wait_drives_online();
    let s = if s["detail"]["all_calibrated"] == true {
        s
    } else {
        // The calibration event follows the drive's configuration within a cycle.
        c.wait_status("all calibrated", |s| s["detail"]["all_calibrated"] == true)
    };
    assert_eq!(
        s["detail"]["calibrated"],
        json!([true, true, true, true, true, true]),
        "{s}"
    );
    assert_positions_true(&mut c);
}
