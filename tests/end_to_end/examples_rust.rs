//! The Rust examples of `examples/rust/` (binaries of the `mcm-client` crate) run against the
//! simulated arm, one after the other on one MCM, each checked by its output and by its effect
//! on the arm (the simulation's ground truth, the state, the CSV it writes).

use crate::common;

use common::square::{TcpWatch, assert_square};
use common::{Mcm, number_after};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longest run of one example (the first one calibrates: about 12 s).
const EXAMPLE_TIMEOUT: Duration = Duration::from_secs(90);

/// An example's binary (a binary of `mcm-client`), as the test command built it for the
/// client's own integration tests (`common::built`).
fn example(name: &str) -> PathBuf {
    common::built::Executable {
        name,
        kind: "bin",
        test: false,
        manifest: "client/Cargo.toml",
    }
    .path()
}

/// Run an example to its end (bounded); its stdout, after checking it succeeded.
fn run(name: &str, args: &[&str]) -> String {
    let out_path = std::env::temp_dir().join(format!("mcm-ex-{}-{name}.out", std::process::id()));
    let out = std::fs::File::create(&out_path).unwrap();
    let mut child = Command::new(example(name))
        .args(args)
        .stdin(Stdio::null())
        .stdout(out)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("start example {name}: {e}"));
    let deadline = Instant::now() + EXAMPLE_TIMEOUT;
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("example {name} did not finish within {EXAMPLE_TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stdout = std::fs::read_to_string(&out_path).unwrap();
    let _ = std::fs::remove_file(&out_path);
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
    eprintln!("[{name}] {stdout}{stderr}");
    assert!(
        status.success(),
        "example {name} failed ({status}): {stdout}{stderr}"
    );
    stdout
}

#[test]
fn every_rust_example_runs_against_the_simulated_arm() {
    // The shared-memory loop's answers applied at the cycle rate: timing, so alone.
    let _alone = common::machine::alone();
    let mcm = Mcm::start("exrs");
    let addr = mcm.json.to_string();
    let inst = mcm.instance.clone();
    let tcp = ["--addr", addr.as_str()];
    let shm = ["--instance", inst.as_str()];

    let out = run("calibrate_and_move", &tcp);
    assert!(out.contains("calibrated in"), "{out}");
    assert!(out.contains("axis 1 at 20.000 deg (mode PVT)"), "{out}");
    let q = mcm.client().truth().0;
    assert!((q[0] - 20.0).abs() < 0.2, "axis 1 truly at {q:?}");

    let out = run("move_all", &tcp);
    assert!(out.contains("move_all planned: longest axis 1"), "{out}");
    assert!(out.contains("largest distance to the target 0.00"), "{out}");
    let q = mcm.client().truth().0;
    for (i, want) in [0.0, 10.0, 20.0, 0.0, 0.0, 0.0].iter().enumerate() {
        assert!((q[i] - want).abs() < 0.2, "axis {} truly at {q:?}", i + 1);
    }

    let out = run("pvt_sine", &tcp);
    assert!(out.contains("streamed 400 points on axis 1"), "{out}");
    assert!(
        (number_after(&out, "peak excursion ") - 20.0).abs() < 0.5,
        "{out}"
    );
    assert!((mcm.client().truth().0[0] - 0.0).abs() < 0.2);

    // VELOCITY_CONTROL: axis 1 out at +10 deg/s for 1 s and back at -10 deg/s (ramped within
    // its acceleration and jerk limits), then HOLD: out by about 10 deg, back near its start.
    let out = run("jog_velocity", &tcp);
    let (start, far, end) = (
        number_after(&out, "start "),
        number_after(&out, "farthest "),
        number_after(&out, "end "),
    );
    assert!(number_after(&out, "velocity jog: ") > 300.0, "{out}");
    assert!((8.0..10.5).contains(&(far - start)), "{out}");
    assert!((end - start).abs() < 3.0, "back near the start: {out}");
    assert!(out.contains("(mode HOLD)"), "{out}");
    let q = mcm.client().truth().0[0];
    assert!((q - end).abs() < 0.1, "axis 1 truly at {q}: {out}");

    // The spring pulls axis 1 by 5 degrees (friction leaves it a little short).
    let mut shm_out = String::new();
    for (name, args) in [("torque_spring_tcp", &tcp), ("torque_spring_shm", &shm)] {
        let before = mcm.client().truth().0[0];
        let out = run(name, args);
        let short = number_after(&out, "deg (");
        assert!(
            short.abs() < 1.5,
            "{name}: {short} deg from the set-point: {out}"
        );
        assert!(out.contains("now HOLD"), "{out}");
        let moved = mcm.client().truth().0[0] - before;
        assert!(
            (3.5..6.5).contains(&moved),
            "{name}: axis 1 truly moved {moved} deg"
        );
        shm_out = out;
    }
    // The control loop's summary: it ran its cycles and read the answers to its commands.
    assert!(number_after(&shm_out, "missed, ") > 300.0, "{shm_out}");
    assert!(
        number_after(&shm_out, "%), ") < 3.0,
        "unanswered: {shm_out}"
    );

    // The logger: one row per state, consecutive cycles but those it says it missed.
    let csv = std::env::temp_dir().join(format!("mcm-ex-{}-state.csv", std::process::id()));
    let csv_arg = csv.to_str().unwrap();
    let out = run(
        "state_logger",
        &[shm[0], shm[1], "--cycles", "200", "--out", csv_arg],
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let _ = std::fs::remove_file(&csv);
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows.len(), 201, "a header and 200 rows");
    assert!(
        rows[0].starts_with("seq,t_s,mode,position_deg_1"),
        "{}",
        rows[0]
    );
    let seqs: Vec<u64> = rows[1..]
        .iter()
        .map(|r| r.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert!(seqs.windows(2).all(|w| w[1] > w[0]), "cycles increase");
    let gaps = seqs.last().unwrap() - seqs[0] + 1 - 200;
    assert_eq!(number_after(&out, "missed ") as u64, gaps, "{out}");
    assert!(rows[1].split(',').nth(2) == Some("HOLD"), "{}", rows[1]);

    // A square of 10 cm in the air with move_linear, watched on the ground truth.
    let watch = TcpWatch::start(&mcm);
    let out = run("draw_square", &tcp);
    let stray = assert_square(&out, &watch.finish(), 0.1);
    assert!(out.contains("square of 0.100 m drawn"), "{out}");
    eprintln!("draw_square: the true TCP within {stray:.6} m of the square");
    // Dropped, not `stop`ped: the simulation's saved state is removed with it.
    drop(mcm);
}

/// The square check of the examples fails a path that leaves the square: a corner cut on the
/// diagonal, a side 2 mm above the plane; it passes the square itself.
#[test]
fn the_square_check_fails_a_path_off_the_square() {
    let out = "start corner [m]: 0.1000 0.2000 0.3000\n";
    let side = 0.1;
    let along = |a: [f64; 3], b: [f64; 3]| {
        (0..=100).map(move |i| {
            let s = f64::from(i) / 100.0;
            [0, 1, 2].map(|k| a[k] + s * (b[k] - a[k]))
        })
    };
    let c = [
        [0.1, 0.2, 0.3],
        [0.2, 0.2, 0.3],
        [0.2, 0.3, 0.3],
        [0.1, 0.3, 0.3],
    ];
    let square: Vec<[f64; 3]> = (0..4).flat_map(|i| along(c[i], c[(i + 1) % 4])).collect();
    assert!(assert_square(out, &square, side) < 1e-12);
    let cut: Vec<[f64; 3]> = along(c[0], c[2]).chain(along(c[2], c[0])).collect();
    let mut high = square.clone();
    for p in &mut high[110..190] {
        p[2] += 0.002;
    }
    for path in [cut, high] {
        let failed = std::panic::catch_unwind(|| assert_square(out, &path, side)).is_err();
        assert!(failed, "a path off the square passed");
    }
}
