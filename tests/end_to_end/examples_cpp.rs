//! The C and C++ API (`capi/`) as an integrator uses it: the C header compiles as C, CMake
//! installs the library (`cmake --install`), the C++ examples of `examples/cpp/` build against
//! it with `find_package(mcm)` and the system compiler (and through `add_subdirectory` too),
//! and run against one simulated arm, each checked by its output and its effect on the arm.
//!
//! The library is the `libmcm_c.a` cargo built for this test (the root package dev-depends on
//! `mcm-capi`, so it is in this test's `deps/` directory): no nested cargo build, no network.
//! Needs `cmake`, `make` (CMake's default generator) and a C++17 compiler (`c++`) in `PATH`;
//! without them the test says it is skipped, except when `CI` is set, where it fails (`.ci/run`
//! installs cmake, make and g++).

use crate::common;

use common::square::{TcpWatch, assert_square};
use common::{Mcm, find_program, number_after};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longest run of one example (the first one calibrates: about 12 s).
const EXAMPLE_TIMEOUT: Duration = Duration::from_secs(90);

/// Run a build step to its end; its stdout, after checking it succeeded.
fn step(what: &str, cmd: &mut Command) -> String {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot run {cmd:?}: {e}"));
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{what} failed ({}): {cmd:?}\n{text}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

/// Run an example to its end (bounded); its exit success, stdout and stderr.
fn run(exe: &Path, args: &[&str]) -> (bool, String, String) {
    let name = exe.file_name().unwrap().to_string_lossy().to_string();
    let out_path =
        std::env::temp_dir().join(format!("mcm-excpp-{}-{name}.out", std::process::id()));
    let mut child = Command::new(exe)
        .args(args)
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out_path).unwrap())
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
    eprintln!("[{name} {}] {stdout}{stderr}", args.join(" "));
    (status.success(), stdout, stderr)
}

/// Run an example that must succeed; its stdout.
fn run_ok(exe: &Path, args: &[&str]) -> String {
    let (ok, out, err) = run(exe, args);
    assert!(ok, "{} failed: {out}{err}", exe.display());
    out
}

/// Build the examples as docs/clients.md says: install the library, then find_package; and
/// once through add_subdirectory. The directory of the built examples.
fn build_examples(lib_dir: &Path) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("examples-cpp");
    let _ = std::fs::remove_dir_all(&work);
    let (lib_build, prefix, examples) = (work.join("capi"), work.join("prefix"), work.join("ex"));
    let lib = format!("-DMCM_RUST_LIB_DIR={}", lib_dir.display());
    step(
        "configure capi/",
        Command::new("cmake")
            .arg("-S")
            .arg(root.join("capi"))
            .arg("-B")
            .arg(&lib_build)
            .arg(&lib),
    );
    step(
        "build capi/",
        Command::new("cmake").arg("--build").arg(&lib_build),
    );
    step(
        "install capi/",
        Command::new("cmake")
            .arg("--install")
            .arg(&lib_build)
            .arg("--prefix")
            .arg(&prefix),
    );
    for f in [
        "include/mcm/mcm.h",
        "include/mcm/mcm.hpp",
        "lib/libmcm_c.a",
        "lib/cmake/mcm/mcmConfig.cmake",
    ] {
        assert!(prefix.join(f).is_file(), "the install has no {f}");
    }
    step(
        "configure examples/cpp with find_package(mcm)",
        Command::new("cmake")
            .arg("-S")
            .arg(root.join("examples/cpp"))
            .arg("-B")
            .arg(&examples)
            .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display())),
    );
    let out = step(
        "build examples/cpp",
        Command::new("cmake").arg("--build").arg(&examples),
    );
    assert!(
        !out.contains("warning:"),
        "the examples build with warnings:\n{out}"
    );
    // The fallback without installing: add_subdirectory of capi/ (one example is enough).
    let sub = work.join("ex-sub");
    step(
        "configure examples/cpp with add_subdirectory",
        Command::new("cmake")
            .arg("-S")
            .arg(root.join("examples/cpp"))
            .arg("-B")
            .arg(&sub)
            .arg("-DMCM_FROM_SOURCE=ON")
            .arg(&lib),
    );
    step(
        "build status_and_hold with add_subdirectory",
        Command::new("cmake")
            .arg("--build")
            .arg(&sub)
            .args(["--target", "status_and_hold"]),
    );
    assert!(sub.join("status_and_hold").is_file());
    examples
}

#[test]
fn cpp_examples_build_with_cmake_and_run_against_the_simulated_arm() {
    // The build loads the machine before the MCM starts.
    common::machine::share();
    let missing: Vec<&str> = ["cmake", "make", "c++", "cc"]
        .into_iter()
        .filter(|p| find_program(p).is_none())
        .collect();
    if !missing.is_empty() {
        common::skip(
            "cpp_examples_build_with_cmake_and_run_against_the_simulated_arm",
            &format!(
                "{} not found in PATH (install with `apt-get install cmake make g++`; .ci/run \
                 does so on CI)",
                missing.join(" and ")
            ),
        );
        return;
    }
    let exe = std::env::current_exe().expect("the test's path");
    let lib_dir = exe.parent().expect("target/<profile>/deps").to_path_buf();
    assert!(
        lib_dir.join("libmcm_c.a").is_file(),
        "no libmcm_c.a in {}: the root package dev-depends on mcm-capi, so cargo builds it for this test",
        lib_dir.display()
    );

    // The generated header is valid C on its own (C99, every warning an error).
    let header = Path::new(env!("CARGO_MANIFEST_DIR")).join("capi/include/mcm/mcm.h");
    step(
        "compile mcm.h as C",
        Command::new("cc")
            .args([
                "-std=c99",
                "-Wall",
                "-Wextra",
                "-Werror",
                "-fsyntax-only",
                "-x",
                "c",
            ])
            .arg(&header),
    );

    // The C++ layer without exceptions: an example that uses none compiles under
    // -fno-exceptions (Result::value() then aborts with the message instead of throwing).
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    step(
        "compile calibrate_and_move.cpp with -fno-exceptions",
        Command::new("c++")
            .args([
                "-std=c++17",
                "-fno-exceptions",
                "-Wall",
                "-Wextra",
                "-Werror",
                "-fsyntax-only",
            ])
            .arg(format!("-I{}", root.join("capi/include").display()))
            .arg(root.join("examples/cpp/calibrate_and_move.cpp")),
    );

    let bin = build_examples(&lib_dir);
    let mcm = Mcm::start("excpp");
    let addr = mcm.json.to_string();
    let inst = mcm.instance.clone();

    // Status and hold; an error as a value carries the MCM's own words and code.
    let out = run_ok(&bin.join("status_and_hold"), &["--addr", &addr]);
    assert!(out.contains("connected to P-Rob2 (MCM "), "{out}");
    assert!(out.contains("mode OFF, all calibrated: no"), "{out}");
    assert!(out.contains("hold: mode HOLD, positions ["), "{out}");
    assert!(
        out.contains(
            "move_axis 9: MCM_ERR_INVALID: move_axis: argument \"axis_index\" = 9 is not allowed; expected an axis number from 1 to 6"
        ),
        "{out}"
    );
    let status = mcm.client().request(r#"{"command":"status"}"#);
    assert_eq!(status["operating_mode"], "HOLD", "{status}");

    // Calibrate and move: the arm truly arrives.
    let out = run_ok(&bin.join("calibrate_and_move"), &["--addr", &addr]);
    assert!(out.contains("calibrated in"), "{out}");
    assert!(out.contains("axis 1 at 20.000 deg (mode PVT)"), "{out}");
    let q = mcm.client().truth().0;
    assert!((q[0] - 20.0).abs() < 0.2, "axis 1 truly at {q:?}");

    // The torque loop over shared memory: the spring pulls axis 1 by about 5 degrees
    // (friction leaves it a little short), every cycle answered through the C++ callback.
    let before = mcm.client().truth().0[0];
    let out = run_ok(&bin.join("torque_spring_shm"), &["--instance", &inst]);
    let short = number_after(&out, "deg (");
    assert!(short.abs() < 1.5, "{short} deg from the set-point: {out}");
    assert!(out.contains("now HOLD"), "{out}");
    let moved = mcm.client().truth().0[0] - before;
    assert!(
        (3.5..6.5).contains(&moved),
        "axis 1 truly moved {moved} deg"
    );
    assert!(number_after(&out, "control loop: ") > 300.0, "{out}");
    assert!(number_after(&out, "%), ") < 3.0, "unanswered: {out}");
    let status = mcm.client().request(r#"{"command":"status"}"#);
    assert_eq!(status["operating_mode"], "HOLD", "{status}");

    // A square of 10 cm in the air with move_linear, watched on the ground truth.
    let watch = TcpWatch::start(&mcm);
    let out = run_ok(&bin.join("draw_square"), &["--addr", &addr]);
    let stray = assert_square(&out, &watch.finish(), 0.1);
    assert!(out.contains("square of 0.100 m drawn"), "{out}");
    eprintln!("draw_square (C++): the true TCP within {stray:.6} m of the square");

    // An instance that does not run: the error names it, the exit code says it failed.
    let (ok, _, err) = run(
        &bin.join("torque_spring_shm"),
        &["--instance", "no-such-mcm-excpp"],
    );
    assert!(!ok, "connecting to a missing instance must fail");
    assert!(
        err.contains("MCM_ERR_NOT_RUNNING") && err.contains("\"no-such-mcm-excpp\" is not running"),
        "{err}"
    );
    drop(mcm);
}
