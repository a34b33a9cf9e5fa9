//! The command line of `mcm-rt` (also `mcm rt`). Runs before the cycle, not inside it.

use crate::runner::{self, RunOptions};
use clap::Parser;
use mcm_shared::config::RobotConfig;
use mcm_shared::service::ServiceNames;
use std::path::PathBuf;
use std::process::ExitCode;

/// Run the MCM's real-time cycle: it owns the CAN bus (or the simulated robot) and serves
/// commands through iceoryx2 shared memory.
#[derive(Parser, Debug)]
#[command(name = "mcm-rt", version, about)]
struct Cli {
    /// Robot configuration file (TOML); the embedded P-Rob2 configuration (simulated) when
    /// omitted.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Instance name: prefix of the shared-memory services (several MCMs can share a machine).
    #[arg(long, default_value = ServiceNames::DEFAULT_INSTANCE)]
    instance: String,
    /// Run even when memory locking, SCHED_FIFO or CPU pinning is not possible (says so once).
    #[arg(long)]
    allow_non_realtime: bool,
    /// Log every bus frame in candump format to this file.
    #[arg(long)]
    candump: Option<PathBuf>,
}

/// Run `mcm-rt` with these command-line arguments (the first is the program name).
pub fn main<I, T>(args: I) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = Cli::parse_from(args);
    let config = match &cli.config {
        Some(p) => RobotConfig::from_file(p),
        None => Ok(RobotConfig::prob2_default()),
    };
    let result = config.map_err(|e| e.to_string()).and_then(|config| {
        let names = ServiceNames::new(&cli.instance).map_err(|e| e.to_string())?;
        Ok(RunOptions {
            config,
            names,
            allow_non_realtime: cli.allow_non_realtime,
            candump: cli.candump,
        })
    });
    let opts = match result {
        Ok(o) => o,
        Err(e) => {
            eprintln!("mcm-rt: {e}");
            return ExitCode::FAILURE;
        }
    };
    runner::install_signal_handlers();
    let instance = opts.names.instance().to_string();
    let backend = format!("{:?}", opts.config.bus.backend).to_lowercase();
    let started = move |report: &crate::realtime::RtReport| {
        if !report.is_realtime() {
            eprintln!("mcm-rt: WARNING: {report}; running anyway (--allow-non-realtime)");
        }
        println!("mcm-rt ready instance={instance} bus={backend}");
    };
    match runner::run(opts, started) {
        Ok(summary) => {
            eprintln!(
                "mcm-rt: stopped after {} cycles, {} overruns, wake-up latency p99 {} us, max {} us",
                summary.cycles,
                summary.overruns,
                summary.latency_p99_ns / 1000,
                summary.latency_max_ns / 1000
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("mcm-rt: {e}");
            ExitCode::FAILURE
        }
    }
}
