//! End to end: `identify_payload` finds a load the configuration does not know. The simulated
//! arm carries 2.0 kg at 60 mm (`sim` `true_tool`) while the configuration's tool is nothing
//! (`tool::unknown_load`). The estimate must be within 5 % in mass and 10 mm in centre of
//! mass, the procedure under 30 s of robot time (the status's `time`, the controller's clock);
//! with `apply` the released arm that sagged before stays where it is left (below 0.1 deg/s on
//! every axis, on the simulation's ground truth, as `tool.rs` measures).

use crate::release::Arm;
use crate::tool::{COM_M, MASS_KG, assert_sags, released_drift, to_pose, unknown_load};

use crate::common::{assert_status, max_diff, time_of};
use std::time::Duration;

/// The procedure's bound in robot time [s] (the contract's).
const LIMIT_S: f64 = 30.0;

/// How long a client waits for the answer: the gateway waits up to 60 s.
const ANSWER_WITHIN: Duration = Duration::from_secs(70);

#[test]
fn an_unknown_load_is_identified_and_applied_and_the_released_arm_then_stays() {
    let (_config, _mcm, mut c) = unknown_load("payload");

    // Before: the unknown load makes the released arm sag.
    assert_sags(&mut c);

    to_pose(&mut c);
    let start = c.truth().0;
    let t0 = time_of(&c.detail());
    let r = c.request_within(
        r#"{"command":"identify_payload","arguments":{"apply":true}}"#,
        ANSWER_WITHIN,
    );
    let t1 = time_of(&c.detail());
    assert_eq!(r["result_type"], "payload", "{r}");
    let mass = r["mass"].as_f64().unwrap();
    let com: Vec<f64> = r["center_of_mass"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let off = com
        .iter()
        .zip(COM_M)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    eprintln!("identified {r} in {:.2} s of robot time", t1 - t0);
    assert!(
        (mass - MASS_KG).abs() < 0.05 * MASS_KG,
        "mass {mass} kg, truth {MASS_KG} kg: {r}"
    );
    assert!(off < 0.010, "centre of mass {off} m from the truth: {r}");
    assert!(r["residual"].as_f64().is_some_and(f64::is_finite), "{r}");
    assert!(t1 - t0 < LIMIT_S, "{} s of robot time", t1 - t0);
    assert_status(&c.detail(), "HOLD");
    assert!(
        max_diff(&c.truth().0, &start) < 0.05,
        "back where it started"
    );

    // `apply`: the estimate is the tool's load now (the result rounds its figures to 1e-6).
    let tool = &c.detail()["detail"]["tool"];
    let applied: Vec<f64> = std::iter::once(&tool["mass"])
        .chain(tool["center_of_mass"].as_array().unwrap())
        .map(|v| v.as_f64().unwrap())
        .collect();
    let estimated: Vec<f64> = std::iter::once(mass).chain(com.iter().copied()).collect();
    assert!(
        applied
            .iter()
            .zip(&estimated)
            .all(|(a, e)| (a - e).abs() <= 1e-6),
        "the tool {tool} is the estimate {r}"
    );

    // After: the released arm stays where it is left.
    let drift = released_drift(&mut c, 0.5, 2.0);
    assert!(
        drift < 0.1,
        "after identify_payload with apply the released arm stays: {drift} deg/s on the worst axis"
    );
}
