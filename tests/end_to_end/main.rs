//! The end-to-end tests of the real processes that can run side by side: one test executable,
//! one module per subject (`cargo test --test end_to_end modes::` runs one subject).
//!
//! Most of these tests start an MCM on the simulated arm and then wait on it: a move, a
//! calibration, a timeout takes its time on the robot's clock, and such a test keeps a tenth of
//! a core busy (`modes::`: 74 s of wall time, 8 s of CPU time). They therefore run
//! [`THREADS`] at a time, not one per core as a test executable does by default; every test
//! takes its own ports, instance name, network namespace and ROS domain
//! (`common::unique_instance` and the like), so any of them can run beside any other.
//! `--test-threads N` or `RUST_TEST_THREADS` chooses otherwise.
//!
//! One executable and not one per subject: each executable compiles `common` and links the whole
//! workspace again (the 36 test executables of `tests/` took 105 s to build from scratch on two
//! cores; this one and the four below take 21 s).
//!
//! The end-to-end tests that need the machine to themselves have their executables of their own
//! and run alone: `tests/calibration_stress.rs` (it loads every CPU on purpose), `tests/vm/`
//! (one guest under software emulation, with the MCM's timing inside it), `tests/builds.rs`
//! (a `cargo check`).

#[path = "../common/mod.rs"]
mod common;

mod argument_texts;
mod capi_cartesian;
mod capi_realtime;
mod cartesian;
mod cartesian_state;
mod cartesian_velocity;
mod command_path;
mod cross_protocol;
mod deb_package;
mod doc_references;
mod drive_bus;
mod error_codes;
mod examples_cpp;
mod examples_python;
mod examples_ros2;
mod examples_rust;
mod hmi;
mod hmi_cartesian;
mod hmi_cartesian_motion;
mod hmi_tmux;
mod hostile_connections;
mod hostile_lifecycle;
mod hostile_ownership;
mod kinematics_pinocchio;
mod modes;
mod modes_restart;
mod move_linear;
mod payload;
mod protocol_examples;
mod python_layout;
mod release;
mod replan;
mod ros2;
mod ros2_read_only;
mod ros2_security;
mod ros2_venv;
mod safety;
mod sd_notify;
mod skeleton;
mod socketcan;
mod systemd_units;
mod tool;
mod velocity;
mod web;
mod zmq;

/// How many tests run at once unless `--test-threads` or `RUST_TEST_THREADS` says otherwise.
pub const THREADS: &std::ffi::CStr = c"4";

/// Before `main` (the test harness reads `RUST_TEST_THREADS` when it starts): [`THREADS`] when
/// the environment does not choose. Only libc, as life before `main` requires.
#[ctor::ctor(unsafe)]
fn default_test_threads() {
    // SAFETY: both are NUL-terminated string literals; before `main` this process has one
    // thread, so nothing reads the environment while it changes; `overwrite` 0 keeps a value the
    // caller set.
    unsafe {
        libc::setenv(c"RUST_TEST_THREADS".as_ptr(), THREADS.as_ptr(), 0);
    }
}
