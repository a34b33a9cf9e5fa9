//! The command line of `mcm-rt` (also `mcm rt`). Runs before the cycle, not inside it.

use crate::runner::{self, RunOptions};
use clap::Parser;
use mcm_shared::cli::CommonArgs;
use mcm_shared::service::ServiceNames;
use std::ffi::OsString;
use std::path::PathBuf;
use std::process::ExitCode;

/// Run the MCM's real-time cycle: it owns the CAN bus (or the simulated robot) and serves
/// commands through iceoryx2 shared memory.
#[derive(Parser, Debug)]
#[command(name = "mcm-rt", version, about)]
struct Cli {
    #[command(flatten)]
    common: CommonArgs,
    /// Run even when memory locking, SCHED_FIFO or CPU pinning is not possible (says so once).
    #[arg(long)]
    allow_non_realtime: bool,
    #[command(flatten)]
    log: LogArgs,
}

/// Bus logging (also an argument of the `mcm` launcher, which passes it on).
#[derive(clap::Args, Debug, Clone, PartialEq, Eq)]
pub struct LogArgs {
    /// Log every CAN frame in candump format to this file.
    #[arg(long)]
    pub candump: Option<PathBuf>,
}

impl LogArgs {
    /// The same arguments as a command line.
    pub fn to_args(&self) -> Vec<OsString> {
        match &self.candump {
            Some(c) => vec!["--candump".into(), c.clone().into_os_string()],
            None => Vec::new(),
        }
    }
}

/// Run `mcm-rt` with these command-line arguments (the first is the program name).
pub fn main<I, T>(args: I) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = Cli::parse_from(args);
    let config = cli.common.load_config();
    let result = config.map_err(|e| e.to_string()).and_then(|config| {
        let names = ServiceNames::new(&cli.common.instance).map_err(|e| e.to_string())?;
        Ok(RunOptions {
            config,
            names,
            allow_non_realtime: cli.allow_non_realtime,
            candump: cli.log.candump,
        })
    });
    let opts = match result {
        Ok(o) => o,
        Err(e) => {
            eprintln!("mcm-rt: {e}");
            return ExitCode::FAILURE;
        }
    };
    if let Err(e) = crate::preflight::check(&opts.config, !opts.allow_non_realtime) {
        eprintln!("mcm-rt: {e}");
        return ExitCode::FAILURE;
    }
    if let Err(e) = crate::signals::install() {
        eprintln!("mcm-rt: cannot install the SIGINT/SIGTERM handlers: {e}");
        return ExitCode::FAILURE;
    }
    // The main thread only waits for the cycle thread: off the cycle's CPU like every helper.
    if let Err(e) = crate::realtime::setup_helper_thread(opts.config.cycle.cpu) {
        eprintln!("mcm-rt: {e}");
        return ExitCode::FAILURE;
    }
    // systemd's notifications (`Type=notify`), from a thread of their own placed like this
    // one; nothing without NOTIFY_SOCKET.
    let (to_systemd, ready_for_systemd) = std::sync::mpsc::sync_channel::<String>(1);
    if let Err(e) = crate::systemd_notify::start(ready_for_systemd) {
        eprintln!("mcm-rt: cannot start the thread that notifies systemd: {e}");
        return ExitCode::FAILURE;
    }
    // The line the launcher reads (`mcm_shared::ready`).
    let ready = mcm_shared::ready::RtReady {
        instance: opts.names.instance().to_string(),
        bus: opts.config.bus.backend,
    };
    let started = move |report: &crate::realtime::RtReport| {
        if !report.is_realtime() {
            eprintln!("mcm-rt: WARNING: {report}; running anyway (--allow-non-realtime)");
        }
        println!("{ready}");
        // Before the first cycle; the channel has room for this one line.
        let _ = to_systemd.try_send(ready.to_string());
    };
    match runner::run(opts, started) {
        Ok(summary) => {
            let f = summary.figures;
            eprintln!(
                "mcm-rt: stopped after {} cycles, {} overruns, {} over the work budget, wake-up latency p99 {} us, max {} us, {} failed command receives, {} failed state notifications, at most {} commands waiting",
                f.cycles,
                f.overruns,
                f.over_budget,
                f.latency_p99_ns / 1000,
                f.latency_max_ns / 1000,
                f.command_receive_errors,
                f.notify_failures,
                f.most_waiting
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("mcm-rt: {e}");
            ExitCode::FAILURE
        }
    }
}
