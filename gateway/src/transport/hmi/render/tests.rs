use super::*;
use mcm_shared::command::Axis;
use mcm_shared::protocol::results::{Info, MoveAllResult, SimResult};
use mcm_shared::reply::{InfoReply, MoveAllPlan, Reason, SafetyError};

fn safety_error(reason: Reason) -> SafetyError {
    SafetyError {
        seq: 3,
        cycle: 100,
        unix_ns: 0,
        reason,
    }
}

fn status_of(st: &StateSample, detail: bool) -> Status {
    Status::from_state(st, detail).unwrap()
}

fn cfg() -> RobotConfig {
    RobotConfig::prob2_default()
}

fn state(mode: Mode) -> StateSample {
    let mut s = StateSample {
        mode: mode.to_wire(),
        t_ns: 12_345_000_000,
        position: [1.0, -2.5, 30.0, 0.0, 0.0, 170.0],
        velocity: [0.0, 0.0, 12.25, 0.0, 0.0, 0.0],
        current: [0.1, 2.0, 1.5, 0.0, 0.0, 0.0],
        i2t: [0.5; 6],
        ..StateSample::default()
    };
    s.axis_flags = [AXIS_CALIBRATED; 6];
    s.flags = STATE_ALL_CALIBRATED;
    s.timing.period_ns = 5_000_000;
    s
}

#[test]
fn status_table_is_aligned_with_units() {
    let st = state(Mode::Hold);
    let text = strip_ansi(&status(&status_of(&st, false), &cfg(), Some(&st)));
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].starts_with("mode HOLD - axes hold their positions"),
        "{text}"
    );
    assert!(lines[0].contains("t = 12.345 s"), "{text}");
    assert!(lines[1].contains("position") && lines[1].contains("current"));
    assert!(lines[2].contains("deg") && lines[2].contains("deg/s") && lines[2].ends_with('A'));
    assert_eq!(
        lines[5], "   3  elbow          30.000      12.250       1.500",
        "{text}"
    );
    assert_eq!(
        lines[1].len(),
        lines[2].len(),
        "header and units line up:\n{text}"
    );
    assert_eq!(
        lines[2].len(),
        lines[3].len(),
        "units and rows line up:\n{text}"
    );
    assert_eq!(lines.len(), 9, "{text}");
    assert!(!text.contains("commanded"));
}

#[test]
fn detailed_status_and_notes() {
    let mut st = state(Mode::Error);
    st.axis_flags[4] = 0;
    st.flags = STATE_ESTOP;
    st.last_error = safety_error(Reason::FollowingError {
        axis: Axis::new(2).unwrap(),
        error_deg: 2.5,
        band_deg: 2.0,
    })
    .encode();
    let text = strip_ansi(&status(&status_of(&st, true), &cfg(), Some(&st)));
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].contains("mode ERROR") && lines[0].contains("`hold` clears"));
    for col in ["commanded", "measured", "foll. err", "i2t", "calibrated"] {
        assert!(lines[1].contains(col), "{col}: {text}");
    }
    assert!(lines[3].ends_with("50.0         yes"), "{text}");
    assert!(lines[7].ends_with("NO"), "{text}");
    assert!(text.contains("hardware:  drives online 0/6"), "{text}");
    assert!(text.contains("PVT queue: 0 of 0 points"), "{text}");
    assert!(text.contains("cycle:     5.000 ms (200 Hz)"), "{text}");
    assert!(
        text.contains("bus:       bad frames 0, frames dropped 0, events dropped 0, bus errors 0"),
        "{text}"
    );
    assert!(text.contains("emergency stop PRESSED"), "{text}");
    assert!(text.contains("not calibrated: axis 5 "), "{text}");
    assert!(
        text.contains("last error: safety check tripped: following error: axis 2"),
        "{text}"
    );
    assert_eq!(lines[1].len(), lines[3].len(), "{text}");
}

#[test]
fn detailed_status_shows_the_bus_counters() {
    let mut st = state(Mode::Hold);
    st.bus.bad_frames = 2;
    st.bus.bus_errors = 7;
    let text = status(&status_of(&st, true), &cfg(), Some(&st));
    assert!(
        text.contains(&format!(
            "bus:       {YELLOW}bad frames 2, frames dropped 0, events dropped 0, bus errors 7{RESET}"
        )),
        "{text}"
    );
    let plain = strip_ansi(&status(&status_of(&st, false), &cfg(), Some(&st)));
    assert!(!plain.contains("bad frames"), "only in the detail: {plain}");
}

#[test]
fn move_all_timing() {
    let plan = MoveAllPlan {
        velocities_deg_s: [10.0, 20.0, 0.0, 0.0, 0.0, 30.0],
        longest: Axis::new(6).unwrap(),
        duration_s: 1.5,
    };
    let text = strip_ansi(&answer(
        "move_all",
        &Answer::MoveAll(MoveAllResult::from(&plan)),
        &cfg(),
        None,
    ));
    assert!(
        text.starts_with("OK - every axis arrives within 1.500 s; axis 6 (flange) takes longest"),
        "{text}"
    );
    assert!(text.contains("   2  shoulder       20.000\n"), "{text}");
    assert!(
        text.contains("   6  flange         30.000  <- longest"),
        "{text}"
    );
}

#[test]
fn info_and_sim_tables() {
    let info = InfoReply {
        num_axes: 6,
        period_s: 0.005,
    };
    let text = strip_ansi(&answer(
        "info",
        &Answer::Initialization(Info::new(&cfg(), &info, true)),
        &cfg(),
        None,
    ));
    assert!(text.starts_with("P-Rob2, MCM "), "{text}");
    assert!(
        text.contains("6 axes, cycle 5.000 ms (200 Hz), simulated robot"),
        "{text}"
    );
    assert!(
        text.contains("   1  base        -170.0     170.0       90.0"),
        "{text}"
    );
    let mut st = state(Mode::Hold);
    st.sim_true_position[0] = 1.25;
    let text = strip_ansi(&answer(
        "sim",
        &Answer::Sim(SimResult::from_state(&st)),
        &cfg(),
        None,
    ));
    assert!(text.contains("emergency switch released"), "{text}");
    assert!(text.contains("   1  base              1.250"), "{text}");
}

#[test]
fn errors_say_how_to_fix_them() {
    let st = state(Mode::Hold);
    let msg = Generic::error(
        ErrorCode::WrongMode,
        "move_axis refused: not allowed in mode HOLD",
    );
    let text = strip_ansi(&error("move_axis", &msg, Some(&st)));
    assert_eq!(
        text,
        "error [wrong_mode]: move_axis refused: not allowed in mode HOLD\n  hint: `move_axis` is accepted in PVT; \
         the mode is HOLD. Enter PVT mode first: `pvt`.\n"
    );
    let text = strip_ansi(&error("move_axis", &msg, Some(&state(Mode::Release))));
    assert!(
        text.ends_with("the mode is RELEASE. Enter PVT mode first: `hold`, then `pvt`.\n"),
        "{text}"
    );
    let text = strip_ansi(&answer(
        "status",
        &Answer::error(
            ErrorCode::CoreUnavailable,
            "status failed: the real-time core (mcm-rt, instance `x`) is not running or not answering",
        ),
        &cfg(),
        None,
    ));
    assert!(
        text.contains("hint: the real-time core (mcm-rt) is not running: start it"),
        "{text}"
    );
    let text = strip_ansi(&answer("hold", &Answer::ok(), &cfg(), None));
    assert_eq!(text, "OK\n");
}

#[test]
fn line_errors_show_the_usage() {
    let e = super::super::words::parse_line("move_axis 1", &cfg()).unwrap_err();
    let text = strip_ansi(&line_error(&e));
    assert!(
        text.starts_with(
            "error [missing_argument]: move_axis: missing argument \"target_position\""
        ),
        "{text}"
    );
    assert!(
        text.contains("usage: move_axis <axis_index> <target_position> [velocity_factor]"),
        "{text}"
    );
    assert!(text.contains("`help move_axis`"), "{text}");
    let e = super::super::words::parse_line("stauts", &cfg()).unwrap_err();
    assert!(!line_error(&e).contains("usage"));
}

#[test]
fn safety_errors_prompt_and_banner() {
    let ev = crate::core_link::bridge::SafetyEvent {
        error: Ok(safety_error(Reason::PositionLimit {
            axis: Axis::new(3).unwrap(),
            position_deg: 121.0,
            limit_deg: 120.0,
        })),
        mode: Mode::Error.to_wire(),
        file: "/tmp/f.csv".into(),
    };
    let text = strip_ansi(&safety(&crate::command::result::safety_generic(&ev)));
    assert!(
        text.starts_with("*** safety check tripped: position limit: axis 3"),
        "{text}"
    );
    assert!(
        text.contains("mode is now ERROR; flight recorder: /tmp/f.csv"),
        "{text}"
    );
    assert!(text.contains("`hold` clears"), "{text}");
    assert_eq!(strip_ansi(&prompt(Some(&state(Mode::Pvt)))), "mcm PVT> ");
    assert_eq!(strip_ansi(&prompt(None)), "mcm NO-CORE> ");
    let b = strip_ansi(&banner(&cfg(), Some(&state(Mode::Off)), "default"));
    assert!(
        b.contains(mcm_shared::VERSION) && b.contains("robot: P-Rob2"),
        "{b}"
    );
    assert!(
        b.contains("mode:  OFF - drives powered off") && b.contains("`help`"),
        "{b}"
    );
    let b = strip_ansi(&banner(&cfg(), None, "robot7"));
    assert!(b.contains("instance `robot7`) is not running"), "{b}");
}

#[test]
fn watch_frames() {
    let st = state(Mode::Pvt);
    let f = strip_ansi(&watch_frame(Some(&st), true, &cfg(), "x"));
    assert!(
        f.starts_with("watch: ") && f.contains("mode PVT") && f.contains("calibrated"),
        "{f}"
    );
    let f = strip_ansi(&watch_frame(None, false, &cfg(), "x"));
    assert!(f.contains("not running"), "{f}");
}

/// An OK result says what was done, in words, for the command that gave it.
#[test]
fn an_ok_result_names_what_was_done() {
    let text = answer("calibrate", &Answer::ok(), &cfg(), None);
    assert!(text.contains("calibration finished"), "{text}");
    assert!(text.contains("OK"), "{text}");
}

#[test]
fn inverse_kinematics_table() {
    let r = mcm_shared::protocol::results::InverseKinematicsResult::new([
        [20.0, 30.0, 60.0, -40.0, 50.0, 10.0],
        [20.0, 95.5, -60.0, 140.0, -50.0, -170.0],
    ]);
    let text = strip_ansi(&answer(
        "inverse_kinematics",
        &Answer::InverseKinematics(r),
        &cfg(),
        None,
    ));
    assert!(
        text.starts_with(
            "OK - 2 solutions within the axis limits, the nearest to the seed first\n"
        ),
        "{text}"
    );
    assert!(
        text.contains("solution    axis 1    axis 2    axis 3    axis 4    axis 5    axis 6\n"),
        "{text}"
    );
    assert!(
        text.contains("       1    20.000    30.000    60.000   -40.000    50.000    10.000\n"),
        "{text}"
    );
    assert!(
        text.contains("       2    20.000    95.500   -60.000   140.000   -50.000  -170.000\n"),
        "{text}"
    );
}
