//! End to end: a load the configuration does not know, and `set_tool`. The simulated arm
//! carries 2.0 kg at 60 mm (`sim` `true_tool`) while the configuration's tool is nothing; in
//! RELEASE the arm sags, measured on the simulation's ground truth (`true_position`) over robot
//! time. After `set_tool` with that load the released arm stays where it is left.

use crate::common;
use crate::release::Arm;

use common::{
    EventClient, Mcm, TempConfig, WAIT, assert_ok, assert_status, config_file, max_diff, time_of,
};
use serde_json::json;
use std::time::{Duration, Instant};

/// Where gravity loads the wrist and the elbow [deg].
pub(crate) const POSE: [f64; 6] = [0.0, 45.0, 30.0, 0.0, 30.0, 0.0];
/// The load the configuration does not know: 2.0 kg, 60 mm out along the flange's z axis.
pub(crate) const MASS_KG: f64 = 2.0;
pub(crate) const COM_M: [f64; 3] = [0.0, 0.0, 0.06];

/// Bring the arm to [`POSE`] (PVT, a joint move, once the stop of a `hold` has ended), wait
/// until it rests there, then HOLD.
pub(crate) fn to_pose(c: &mut EventClient) {
    assert_status(&c.request(r#"{"command":"pvt"}"#), "PVT");
    let mv = json!({"command": "move_all",
        "arguments": {"target_positions": POSE, "velocity_factor": 0.5}});
    let deadline = Instant::now() + WAIT;
    let r = loop {
        let r = c.request(&mv.to_string());
        if r["error_code"] != "busy" || Instant::now() > deadline {
            break r;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(r["result_type"], "move_all", "{r}");
    c.wait_until("the arm at the pose, at rest", |_, q, v| {
        max_diff(q, &POSE) < 0.1 && v.iter().all(|x| x.abs() < 0.01)
    });
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
}

/// Release the arm, let it settle for `settle_s`, then the largest true drift rate of an axis
/// over `window_s` of robot time [deg/s].
pub(crate) fn released_drift(c: &mut EventClient, settle_s: f64, window_s: f64) -> f64 {
    assert_status(&c.request(r#"{"command":"release"}"#), "RELEASE");
    c.observe(settle_s, |s, _, _| assert_status(s, "RELEASE"));
    let t0 = time_of(&c.detail());
    let (q0, _) = c.truth();
    let mut last = (t0, q0);
    c.observe(window_s, |s, q, _| last = (time_of(s), *q));
    let (t1, q1) = last;
    assert!(t1 > t0, "robot time went on: {t0} -> {t1}");
    let rate = max_diff(&q1, &q0) / (t1 - t0);
    eprintln!(
        "released: {q0:?} -> {q1:?} in {:.3} s: {rate:.4} deg/s",
        t1 - t0
    );
    assert_status(&c.request(r#"{"command":"hold"}"#), "HOLD");
    rate
}

/// An MCM (instance `name`) whose configuration's tool carries no load, its arm calibrated in
/// HOLD and really carrying [`MASS_KG`] at [`COM_M`] (`sim` `true_tool`); its configuration
/// file (kept while the MCM runs) and its client.
pub(crate) fn unknown_load(name: &str) -> (TempConfig, Mcm, EventClient) {
    let config = config_file(name, |base| {
        base.replace(
            "mass = 3.8                # [kg]",
            "mass = 0.0                # [kg]",
        )
        .replace("com = [0.0, 0.0, 0.08]    #", "com = [0.0, 0.0, 0.0]    #")
    });
    let mcm = Mcm::start_with(name, &["--config", config.path()]);
    let mut c = EventClient::connect(mcm.json);
    c.wait_drives_online();
    c.calibrate();
    let tool = &c.detail()["detail"]["tool"];
    assert_eq!(
        tool["mass"], 0.0,
        "the configuration's tool is nothing: {tool}"
    );
    c.sim(json!({"true_tool": {"mass": MASS_KG, "center_of_mass": COM_M}}));
    (config, mcm, c)
}

/// Released at [`POSE`], the arm with the load its model does not know sags visibly.
pub(crate) fn assert_sags(c: &mut EventClient) {
    to_pose(c);
    let sag = released_drift(c, 0.0, 0.5);
    assert!(
        sag > 1.0,
        "the unknown 2 kg makes the released arm sag: {sag} deg/s"
    );
}

#[test]
fn an_unknown_load_sags_in_release_and_after_set_tool_the_arm_stays_where_it_is_left() {
    let (_config, _mcm, mut c) = unknown_load("tool-release");

    assert_sags(&mut c);

    to_pose(&mut c);
    let set = json!({"command": "set_tool", "arguments": {
        "tcp": {"position": [0.0, 0.0, 0.0], "orientation": [0.0, 0.0, 0.0, 1.0]},
        "mass": MASS_KG, "center_of_mass": COM_M}});
    assert_ok(&c.request(&set.to_string()));
    let tool = &c.detail()["detail"]["tool"];
    assert_eq!(tool["mass"], MASS_KG, "{tool}");
    assert_eq!(tool["center_of_mass"], json!(COM_M), "{tool}");
    let drift = released_drift(&mut c, 0.5, 2.0);
    assert!(
        drift < 0.1,
        "after set_tool the released arm stays: {drift} deg/s on the worst axis"
    );
}
