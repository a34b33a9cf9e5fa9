//! One benchmark run: start the MCM, measure phase after phase, stop it, print the table.
//! A phase that fails is reported in its rows (not measured) and the run goes on.

use crate::Args;
use crate::client::{Client, HOLD, STATUS_DETAIL, line};
use crate::error::BenchError;
use crate::mcm::{Mcm, locate};
use crate::phases::{self, Bench, failed, step};
use crate::report::{Verdict, table};
use mcm_shared::command::{Calibrate, Direction};
use mcm_shared::config::RobotConfig;
use mcm_shared::protocol::DEFAULT_WHICH;
use mcm_shared::service::ServiceNames;
use std::time::{Duration, Instant};

/// The phases, in the order they run.
const PHASES: [&str; 5] = ["latency", "status", "hold", "torque", "stall"];

/// How many samples each phase takes, and its time budget.
pub struct Plan {
    pub latency_secs: u64,
    pub status: usize,
    pub pipelined: usize,
    pub holds: usize,
    pub torque_cycles: u64,
    pub budget: Duration,
}

impl Plan {
    fn new(a: &Args) -> Plan {
        let q = a.quick;
        Plan {
            latency_secs: a.latency_secs.unwrap_or(if q { 10 } else { 60 }),
            status: if q { 2_000 } else { 10_000 },
            pipelined: if q { 5_000 } else { 50_000 },
            holds: if q { 200 } else { 1_000 },
            torque_cycles: a.torque_cycles.unwrap_or(if q { 1_000 } else { 10_000 }),
            budget: Duration::from_secs(if q { 15 } else { 60 }),
        }
    }
}

/// Run everything; `Ok(true)` when every target passed.
pub fn run(args: &Args) -> Result<bool, BenchError> {
    for p in &args.only {
        if !PHASES.contains(&p.as_str()) {
            return Err(BenchError::Setup(format!(
                "--only {p:?} is not a phase; the phases are {}",
                PHASES.join(", ")
            )));
        }
    }
    let cfg = match &args.config {
        Some(path) => RobotConfig::from_file(path)
            .map_err(|e| BenchError::Start(format!("config {}: {e}", path.display())))?,
        None => RobotConfig::prob2_default(),
    };
    let period_ns = cfg.cycle_period_ns();
    let period_us = period_ns / 1_000;
    let period_s = period_ns as f64 / 1e9;
    let kt6 = cfg.axes[5].torque_per_amp();
    let plan = Plan::new(args);
    let binary = locate(args.mcm.as_deref())?;
    let instance = format!("bench-{}", std::process::id());
    let names = ServiceNames::new(&instance).map_err(|e| BenchError::Start(e.to_string()))?;
    step(&format!(
        "starting {} --instance {instance}",
        binary.display()
    ));
    let mut notes = Vec::new();
    // Every client of the benchmark connects from 127.0.0.1: with the default configuration
    // the per-address cap (16) is lifted to the port's whole capacity (64), so that 60
    // flooding connections and the measuring one fit, as they would from many addresses.
    let own_config = match &args.config {
        Some(_) => None,
        None => Some(bench_config(&instance)?),
    };
    if own_config.is_some() {
        notes.push(
            "default config with [gateway.connections] max_per_peer = 64 (all bench clients \
             share 127.0.0.1)"
                .to_string(),
        );
    }
    let config_path = args.config.as_deref().or(own_config.as_deref());
    let mcm = Mcm::start(&binary, &instance, config_path)?;
    let started = Instant::now();

    // Ready: drives online, calibrated (the torque loops need it), in HOLD.
    let mut c = Client::connect(mcm.json)?;
    let wait = Duration::from_secs(60);
    c.wait_status("all drives online", wait, |s| {
        s.detail
            .as_ref()
            .is_some_and(|d| d.drive_online.iter().all(|&online| online))
    })?;
    step("calibrating the simulated arm");
    {
        // On a connection of its own: a motion command makes its client the owner of motion,
        // and ownership ends when the connection closes; the loops later need to own it.
        let mut cal = Client::connect(mcm.json)?;
        cal.set_read_timeout(Duration::from_secs(180))?;
        cal.ok(&line(Calibrate {
            which: DEFAULT_WHICH,
            elbow_direction: Direction::Positive,
            wrist_direction: Direction::Positive,
            force_mechanical_stop: false,
        }))?;
        cal.ok(&HOLD)?;
    }
    c.ok(&HOLD)?;
    let realtime = c
        .status(&STATUS_DETAIL)?
        .detail
        .is_some_and(|d| d.timing.realtime);
    if !realtime {
        notes.push(
            "mcm-rt runs WITHOUT real-time scheduling (not root?): latency figures mean little"
                .into(),
        );
    }

    let mut b = Bench {
        args,
        plan,
        cfg,
        names,
        json: mcm.json,
        gateway_pid: mcm.gateway_pid,
        period_us,
        period_s,
        kt6,
        c,
        rows: Vec::new(),
        notes,
        latency_text: String::new(),
    };
    for (name, phase) in [
        (
            "latency",
            phases::latency as fn(&mut Bench) -> Result<(), BenchError>,
        ),
        ("status", phases::status),
        ("hold", phases::hold),
        ("torque", phases::torque),
        ("stall", phases::stall),
    ] {
        if args.wants(name)
            && let Err(e) = phase(&mut b)
        {
            failed(&mut b.rows, name, &e);
        }
    }
    let Bench {
        c,
        rows,
        notes,
        latency_text: lat_text,
        ..
    } = b;
    drop(c);
    step("stopping the MCM");
    mcm.stop();
    println!(
        "MCM command path benchmark{} ({} s, period {} us, instance {instance})",
        if args.quick { " --quick" } else { "" },
        started.elapsed().as_secs(),
        period_us
    );
    println!();
    if !lat_text.is_empty() {
        print!("{lat_text}");
        println!();
    }
    print!("{}", table(&rows));
    if !notes.is_empty() {
        println!();
        for n in &notes {
            println!("note: {n}");
        }
    }
    Ok(!rows
        .iter()
        .any(|r| r.verdict == Verdict::Fail || r.verdict == Verdict::NotMeasured))
}

/// The embedded P-Rob2 configuration with the per-address connection cap lifted, written to a
/// file named for `instance` in the temporary directory.
fn bench_config(instance: &str) -> Result<std::path::PathBuf, BenchError> {
    let path = std::env::temp_dir().join(format!("mcm-{instance}.toml"));
    let text = format!(
        "{}\n[gateway.connections]\nmax_per_peer = 64\n",
        mcm_shared::config::PROB2_DEFAULT_TOML
    );
    std::fs::write(&path, text).map_err(|e| {
        BenchError::Start(format!(
            "cannot write the benchmark's config {}: {e}",
            path.display()
        ))
    })?;
    Ok(path)
}
