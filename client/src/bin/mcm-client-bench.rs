//! Benchmark of the shared-memory client (not a test: run it on an idle machine).
//!
//! ```sh
//! cargo build --release -p mcm -p mcm-client
//! cargo run --release -p mcm-client --bin mcm-client-bench -- --cycles 10000
//! ```
//!
//! It starts the simulated MCM (the `mcm` binary beside this one, a unique instance, no TCP
//! ports needed beyond free ones), or uses a running one with `--instance NAME`, and measures:
//!
//! 1. `wait_state()`: over `--cycles` states, the cycles missed (target 0) and the sample's age
//!    on wake-up, from the start of the cycle that produced it (`t_ns`) to the return of
//!    `wait_state` (target: p50 below 100 us);
//! 2. the `control(callback)` loop in TORQUE_CONTROL (zero torques: the arm floats, gravity
//!    compensated) over `--cycles` cycles: the share of answers to the state of cycle k that
//!    the core applied in cycle k + 1 (target at least 99.9 %).
//!
//! Each figure is printed with PASS or FAIL against its target; the exit code is 1 when one
//! fails. `--rt-priority N` runs the client as SCHED_FIFO N (needs the privilege); `--cpu N`
//! pins the measuring thread to CPU N (e.g. the core's `cycle.cpu`, see
//! [`mcm_client::placement`]). The MCM it starts keeps its own placement either way.

use clap::Parser;
use mcm_client::launch::SimulatedMcm;
use mcm_client::shm::{ControlOutput, ShmClient};
use mcm_client::{mcm_shared, monotonic_ns};
use mcm_shared::command::TorqueControl;
use std::path::PathBuf;
use std::process::Stdio;
use std::time::Duration;

#[derive(Parser)]
struct Args {
    /// States measured by `wait_state()` (and control cycles, unless `--control-cycles`).
    #[arg(long, default_value_t = 10_000)]
    cycles: u64,
    /// Cycles of the control loop (default: `--cycles`); e.g. `--cycles 120000
    /// --control-cycles 10000` for ten minutes of `wait_state()` at 200 Hz.
    #[arg(long)]
    control_cycles: Option<u64>,
    /// Use the running MCM of this instance instead of starting one.
    #[arg(long)]
    instance: Option<String>,
    /// The `mcm` binary to start (default: beside this executable).
    #[arg(long)]
    mcm: Option<PathBuf>,
    /// Run the measuring thread as SCHED_FIFO with this priority (1 to 99; below the core's
    /// `cycle.priority`), after starting the MCM.
    #[arg(long)]
    rt_priority: Option<i32>,
    /// Pin the measuring thread to this CPU (after starting the MCM, which keeps its own).
    #[arg(long)]
    cpu: Option<usize>,
}

/// The `mcm` binary beside this executable, or `explicit`; started as a unique instance.
fn start_mcm(explicit: Option<PathBuf>) -> Result<SimulatedMcm, String> {
    let binary = match explicit {
        Some(b) => b,
        None => std::env::current_exe()
            .map_err(|e| format!("cannot find this executable: {e}"))?
            .with_file_name("mcm"),
    };
    if !binary.is_file() {
        return Err(format!(
            "no `mcm` binary at {}: build it in the same profile first (`cargo build --release -p mcm -p mcm-client`) or pass --mcm PATH",
            binary.display()
        ));
    }
    let instance = format!("clbench{}", std::process::id());
    SimulatedMcm::start(
        &binary,
        &instance,
        &[],
        Stdio::null(),
        Duration::from_secs(60),
    )
    .map_err(|e| e.to_string())
}

/// The `q`-quantile of sorted values.
fn quantile(sorted: &[u64], q: f64) -> u64 {
    if sorted.is_empty() {
        return 0;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn verdict(pass: bool) -> &'static str {
    if pass { "PASS" } else { "FAIL" }
}

fn main() {
    match run() {
        Ok(true) => {}
        Ok(false) => std::process::exit(1),
        Err(e) => {
            eprintln!("mcm-client-bench: {e}");
            std::process::exit(2);
        }
    }
}

fn run() -> Result<bool, Box<dyn std::error::Error>> {
    let args = Args::parse();
    // Stopped when dropped, at the end of `run`.
    let (_started, instance) = match args.instance {
        Some(i) => (None, i),
        None => {
            let s = start_mcm(args.mcm)?;
            let i = s.instance.clone();
            (Some(s), i)
        }
    };
    // After starting the MCM: it must not inherit the client's policy or placement.
    if let Some(prio) = args.rt_priority {
        let p = libc::sched_param {
            sched_priority: prio,
        };
        // SAFETY: sched_setscheduler on the calling thread (pid 0) with a valid sched_param.
        let r = unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &p) };
        if r != 0 {
            return Err(format!(
                "cannot run as SCHED_FIFO {prio}: {}",
                std::io::Error::last_os_error()
            )
            .into());
        }
        println!("client runs as SCHED_FIFO {prio}");
    }
    if let Some(cpu) = args.cpu {
        mcm_client::placement::pin_current_thread(cpu)?;
        println!("client thread pinned to CPU {cpu}");
    }
    let mut mcm = ShmClient::connect(&instance)?;
    let first = mcm.wait_state()?;
    let period_us = first.timing.period_ns as f64 / 1e3;
    println!(
        "MCM instance {instance}: cycle {period_us:.0} us; {} states, {} control cycles",
        args.cycles,
        args.control_cycles.unwrap_or(args.cycles)
    );

    // 1. wait_state: missed cycles and the sample's age on wake-up.
    let missed_before = mcm.missed_states();
    let mut ages = Vec::with_capacity(args.cycles as usize);
    for _ in 0..args.cycles {
        let s = mcm.wait_state()?;
        ages.push(monotonic_ns().saturating_sub(s.t_ns));
    }
    let missed = mcm.missed_states() - missed_before;
    ages.sort_unstable();
    let us = |ns: u64| ns as f64 / 1e3;
    let p50 = quantile(&ages, 0.5);
    let wait_ok = missed == 0 && p50 < 100_000;
    println!(
        "wait_state: {} states, {missed} missed (target 0); age on wake-up since the cycle's start: p50 {:.1} us (target < 100 us), p99 {:.1} us, p99.9 {:.1} us, max {:.1} us  {}",
        args.cycles,
        us(p50),
        us(quantile(&ages, 0.99)),
        us(quantile(&ages, 0.999)),
        us(*ages.last().unwrap_or(&0)),
        verdict(wait_ok)
    );

    // 2. The control loop in TORQUE_CONTROL.
    if mcm.calibrate_if_needed()? {
        println!("calibrated the simulated arm first");
    }
    mcm.torque_control(TorqueControl {
        timeout_s: Some(0.1),
        gravity_compensation: true,
    })?;
    let mut n = 0;
    let cycles = args.control_cycles.unwrap_or(args.cycles);
    let summary = mcm.control(|_| {
        n += 1;
        if n > cycles {
            ControlOutput::Finish
        } else {
            ControlOutput::Torques([0.0; 6])
        }
    });
    let _ = mcm.hold();
    let summary = summary?;
    let control_ok = summary.on_time_percent() >= 99.9;
    println!(
        "control loop: {summary}; target >= 99.9 % in the next cycle  {}",
        verdict(control_ok)
    );
    Ok(wait_ok && control_ok)
}
