//! The Python client package (`python/`) and every Python example (`examples/python/`) against
//! the simulated arm: the package's unit tests (standard library `unittest`), its live
//! shared-memory tests, each example run as a user would run it, and the effect checked on the
//! simulation's ground truth (the arm moved, the spring gave way, CSV rows, a PNG of a real
//! flight-recorder file). Python comes from a virtual environment under the target directory
//! (`tests/common/python.rs`); without Python the tests are skipped, saying so, or fail when
//! `CI` is set; a pip install that fails (no network) fails them. Every Python test that runs
//! here must run and pass: a skipped one is a failure (unittest counts it in "Ran N").

use crate::common;

use common::python::venv_or_skip;
use common::square::{TcpWatch, assert_square};
use common::{Client, Mcm, WAIT, assert_ok, max_diff, move_all, python, six};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

/// The share [%] of the benchmark's answers (400) that must be applied in the very next cycle
/// here. Measured under test load (`docs/performance.md`, "The Python loop under test load":
/// this file run 8 times, alone and beside other end-to-end test binaries, load average 5 to 9
/// on the 2 vCPUs): 400 of 400 in every run. The target keeps a margin of 20 late answers (the
/// loop stalled for about 0.1 s), below the benchmark's own target for an idle machine
/// (99.9 %); the checks that every answer is replied to stay exact.
const BENCH_TARGET_PERCENT: f64 = 95.0;

/// The modules of `python/tests/` that need what another test sets up, and that test: they
/// skip without it (fail under `CI`), so the package's unit tests leave them out.
const RUN_ELSEWHERE: [(&str, &str); 2] = [
    (
        "test_layout",
        "tests/end_to_end/python_layout.rs (MCM_LAYOUT_JSON, the Rust layouts)",
    ),
    (
        "test_shm_live",
        "shared_memory_client_and_examples_run_at_the_cycle_rate below (MCM_INSTANCE, a running MCM)",
    ),
];

/// Run `examples/python/<name>.py` against `mcm` with `args`; its stdout (it must succeed).
fn example(py: &Path, mcm: &Mcm, name: &str, args: &[&str]) -> String {
    let script = python::repo_root()
        .join("examples/python")
        .join(format!("{name}.py"));
    let port = mcm.json.port().to_string();
    let out = python::run(
        Command::new(py)
            .arg(&script)
            .args(["--host", "127.0.0.1", "--port", &port])
            .args(["--instance", &mcm.instance])
            .args(args)
            .env("PYTHONDONTWRITEBYTECODE", "1"),
    )
    .unwrap_or_else(|e| panic!("example {name}: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    eprintln!("[{name}] {stdout}");
    stdout
}

/// The number right after `marker` in `text`.
fn number_after(text: &str, marker: &str) -> f64 {
    let at = text
        .find(marker)
        .unwrap_or_else(|| panic!("{marker:?} not in the output: {text}"))
        + marker.len();
    let num: String = text[at..]
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | 'e'))
        .collect();
    num.parse()
        .unwrap_or_else(|e| panic!("no number after {marker:?} ({e}): {text}"))
}

/// The simulation's true joint angles.
fn true_position(c: &mut Client) -> [f64; 6] {
    let r = c.request(r#"{"command":"sim"}"#);
    six(&r["true_position"])
}

/// Check the spring examples' report: under the push the axis gave way by about push /
/// stiffness (friction and the still-settling arm take a share), and came back after it.
fn assert_spring(out: &str) {
    let deflection = number_after(out, "deflection under 10.0 Nm");
    let expected = number_after(out, "(push / stiffness =");
    let after = number_after(out, "deg);");
    assert!(
        deflection > 0.5 * expected && deflection < 1.2 * expected,
        "the spring should give way by about {expected} deg, gave {deflection}: {out}"
    );
    assert!(
        after.abs() < 0.5 * deflection,
        "the spring should pull the axis back: {after} deg left of {deflection}: {out}"
    );
}

/// Check a velocity sweep's report (`velocity_sweep.py`, `jog_velocity.rs`): out by about
/// speed x 1 s (the ramps take a share), back near the start, at rest in HOLD where the
/// simulation's ground truth (`truth`, the axis's true angle) says.
fn assert_velocity_sweep(out: &str, truth: f64) {
    let ticks = number_after(out, "velocity sweep:");
    let start = number_after(out, "start ");
    let far = number_after(out, "farthest ");
    let end = number_after(out, "end ");
    assert!(ticks > 300.0, "2 s at 200 Hz answered: {out}");
    assert!(
        (8.0..10.5).contains(&(far - start)),
        "out by {} deg, expected about 10: {out}",
        far - start
    );
    assert!((end - start).abs() < 3.0, "back near the start: {out}");
    assert!(out.contains("(mode HOLD)"), "{out}");
    assert!((truth - end).abs() < 0.1, "truly at {truth} deg: {out}");
}

#[test]
fn python_package_unit_tests_pass() {
    let Some(py) = venv_or_skip("python_package_unit_tests_pass") else {
        return;
    };
    // Every module of python/tests/ but those run elsewhere with what they need.
    let dir = python::repo_root().join("python/tests");
    let mut modules: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter(|n| n.starts_with("test_"))
        .filter_map(|n| n.strip_suffix(".py").map(str::to_string))
        .collect();
    modules.sort();
    for (module, runner) in RUN_ELSEWHERE {
        assert!(
            modules.iter().any(|m| m == module),
            "python/tests/{module}.py (run by {runner}) is gone: update RUN_ELSEWHERE"
        );
    }
    modules.retain(|m| !RUN_ELSEWHERE.iter().any(|(other, _)| m == other));
    let names: Vec<&str> = modules.iter().map(String::as_str).collect();
    let expected = python::tests_defined(&names);
    assert!(expected >= 20, "the package's unit tests: {names:?}");
    let args: Vec<String> = names.iter().map(|m| format!("tests.{m}")).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let log = python::unittest(&py, &args, &[])
        .unwrap_or_else(|e| panic!("the Python package's unit tests failed: {e}"));
    python::assert_all_passed(&log, expected);
}

#[test]
fn tcp_examples_move_the_simulated_arm() {
    let Some(py) = venv_or_skip("tcp_examples_move_the_simulated_arm") else {
        return;
    };
    let mcm = Mcm::start("py-tcp");
    let mut c = mcm.client();
    c.wait_drives_online();

    // The manual's example, from OFF: `release` is refused with a generic ERROR.
    assert_eq!(example(&py, &mcm, "basic", &[]).trim(), "generic");

    let out = example(
        &py,
        &mcm,
        "calibrate_and_move",
        &["--axis", "1", "--target", "20"],
    );
    assert!(out.contains("axis 1 at 20.000 deg"), "{out}");
    let q = true_position(&mut c);
    assert!((q[0] - 20.0).abs() < 0.1, "axis 1 truly at 20 deg: {q:?}");

    let targets = [10.0, -20.0, 30.0, 0.0, 15.0, 0.0];
    let out = example(
        &py,
        &mcm,
        "move_all",
        &["--targets", "10", "-20", "30", "0", "15", "0"],
    );
    assert!(out.contains("longest axis 3"), "{out}");
    let q = true_position(&mut c);
    for (i, (got, want)) in q.iter().zip(targets).enumerate() {
        assert!(
            (got - want).abs() < 0.1,
            "axis {} at {got}, not {want}",
            i + 1
        );
    }

    // A square of 10 cm in the air with move_linear, watched on the ground truth.
    let watch = TcpWatch::start(&mcm);
    let out = example(&py, &mcm, "draw_square", &[]);
    let stray = assert_square(&out, &watch.finish(), 0.1);
    assert!(out.contains("square of 0.100 m drawn"), "{out}");
    eprintln!("draw_square.py: the true TCP within {stray:.6} m of the square");
    // Back where `move_all` left the arm, which the examples and the trip below start from;
    // then the control this client took is given up for the next example.
    let pvt = c.request(r#"{"command":"pvt"}"#);
    assert_eq!(pvt["operating_mode"], "PVT", "{pvt}");
    let back = c.request(&move_all(&targets, 1.0));
    assert_eq!(back["result_type"], "move_all", "{back}");
    c.wait_truth("back at the move_all targets", |p, v| {
        max_diff(p, &targets) < 0.05 && v.iter().all(|x| x.abs() < 0.01)
    });
    assert_ok(&c.request(r#"{"command":"release_control"}"#));

    let out = example(
        &py,
        &mcm,
        "pvt_sine",
        &[
            "--axis",
            "2",
            "--amplitude",
            "5",
            "--period",
            "1.5",
            "--cycles",
            "1",
        ],
    );
    let peak = number_after(&out, "peak excursion");
    assert!((peak - 10.0).abs() < 0.5, "peak excursion {peak}: {out}");
    assert!(out.contains("starved: False"), "{out}");

    let out = example(&py, &mcm, "torque_spring", &["--axis", "1", "--push", "10"]);
    assert!(number_after(&out, "torque loop:") > 100.0, "{out}");
    assert_spring(&out);

    // VELOCITY_CONTROL: axis 2 out at +10 deg/s for 1 s and back at -10 deg/s (ramped within
    // its acceleration and jerk limits), then HOLD: out by about 10 deg, back near its start.
    let out = example(
        &py,
        &mcm,
        "velocity_sweep",
        &["--axis", "2", "--speed", "10"],
    );
    assert_velocity_sweep(&out, true_position(&mut c)[1]);

    let csv = std::env::temp_dir().join(format!("{}-state.csv", mcm.instance));
    let out = example(
        &py,
        &mcm,
        "state_logger",
        &[
            "--duration",
            "1",
            "--interval",
            "0.02",
            "--out",
            csv.to_str().unwrap(),
        ],
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let _ = std::fs::remove_file(&csv);
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows[0].split(',').count(), 20, "header: {}", rows[0]);
    assert!(rows.len() > 20, "expected a row per read over 1 s: {out}");
    let times: Vec<f64> = rows[1..]
        .iter()
        .map(|r| r.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert!(times.windows(2).all(|w| w[1] > w[0]), "rows in time order");
    assert!(
        times[times.len() - 1] - times[0] >= 1.0,
        "1 s on the robot's clock"
    );

    // Trip a check: block axis 2 while it moves; the flight recorder writes its file.
    // Nothing tripped before (a spontaneous error would arrive here first).
    let held = c.request(r#"{"command":"hold"}"#);
    assert_eq!(held["operating_mode"], "HOLD", "{held}");
    c.request(r#"{"command":"pvt"}"#);
    assert_ok(&c.request(
        r#"{"command":"move_axis","arguments":{"axis_index":2,"target_position":30,"velocity_factor":0.5}}"#,
    ));
    c.request(r#"{"command":"sim","arguments":{"block_axis":2}}"#);
    let err = c.recv_matching(|v: &Value| v.get("check").is_some());
    assert_eq!(err["axis"], 2, "{err}");
    let file = PathBuf::from(err["flight_recorder"].as_str().unwrap());
    let deadline = Instant::now() + WAIT;
    while !file.exists() {
        assert!(
            Instant::now() < deadline,
            "no flight-recorder file {file:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let png = std::env::temp_dir().join(format!("{}-trip.png", mcm.instance));
    let out = example(
        &py,
        &mcm,
        "plot_flight_recorder",
        &[
            file.to_str().unwrap(),
            "--out",
            png.to_str().unwrap(),
            "--axis",
            "2",
        ],
    );
    let check = err["check"].as_str().unwrap();
    assert!(out.contains(&format!("{check} trip")), "{out}");
    let bytes = std::fs::read(&png).unwrap();
    let _ = std::fs::remove_file(&png);
    let _ = std::fs::remove_file(&file);
    assert!(
        bytes.starts_with(b"\x89PNG") && bytes.len() > 10_000,
        "a PNG plot"
    );
}

#[test]
fn shared_memory_client_and_examples_run_at_the_cycle_rate() {
    // Every cycle of 4 s answered or counted, the benchmark's share of answers applied in the
    // next cycle: timing, so alone on the machine.
    let _alone = common::machine::alone();
    let Some(py) = venv_or_skip("shared_memory_client_and_examples_run_at_the_cycle_rate") else {
        return;
    };
    let mcm = Mcm::start("py-shm");
    mcm.client().wait_drives_online();
    let out = example(
        &py,
        &mcm,
        "torque_spring_shm",
        &["--axis", "1", "--push", "10"],
    );
    // 4 s on the robot's clock at 200 Hz: every cycle answered or counted as missed.
    let cycles = number_after(&out, "torque loop:");
    let missed = number_after(&out, "cycles,");
    assert!(cycles + missed >= 790.0, "{out}");
    assert_spring(&out);

    let log = python::unittest(
        &py,
        &["tests.test_shm_live"],
        &[("MCM_INSTANCE", mcm.instance.as_ref())],
    )
    .unwrap_or_else(|e| panic!("the live shared-memory tests failed: {e}"));
    python::assert_all_passed(&log, python::tests_defined(&["test_shm_live"]));

    // The benchmark (python/bench/control_loop.py) in TORQUE_CONTROL over 400 cycles, with a
    // target this machine can hold under test load (the benchmark's own 99.9 % is for an idle
    // machine: docs/performance.md): a loop whose answers are applied late as a rule fails it,
    // and so does one whose answers the core does not reply to.
    let port = mcm.json.port().to_string();
    let target = BENCH_TARGET_PERCENT.to_string();
    let out = python::run(
        Command::new(&py)
            .arg(python::repo_root().join("python/bench/control_loop.py"))
            .args(["--host", "127.0.0.1", "--port", &port])
            .args(["--instance", &mcm.instance, "--cycles", "400"])
            .args(["--target", &target]),
    )
    .unwrap_or_else(|e| panic!("the control-loop benchmark failed: {e}"));
    let text = String::from_utf8_lossy(&out.stdout);
    eprintln!("[bench] {text}");
    let cycles = number_after(&text, "cycles ");
    let next = number_after(&text, "applied in the next cycle ");
    let later = number_after(&text, "later ");
    let unanswered = number_after(&text, "unanswered ");
    let share = number_after(&text, "PASS: ");
    assert_eq!(cycles, 400.0, "{text}");
    assert_eq!(
        (next + later, unanswered),
        (400.0, 0.0),
        "every answer replied to: {text}"
    );
    assert!(
        (share - 100.0 * next / 400.0).abs() < 0.001 && share >= BENCH_TARGET_PERCENT,
        "{text}"
    );
}
