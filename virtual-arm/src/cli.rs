//! `mcm-virtual-arm` (also `mcm virtual-arm`): the command line.

use crate::run::{Options, run};
use clap::Parser;
use std::ffi::OsString;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

/// A virtual P-Rob2 on a CAN interface: the MCM's simulated drives and arm physics answer a
/// CANopen master (mcm-rt with bus.backend = "socketcan", or your own) over SocketCAN.
/// Never start it on a bus with real drives: it answers as nodes of the configuration.
#[derive(Debug, Parser)]
#[command(name = "mcm-virtual-arm", version)]
struct Args {
    /// The CAN interface to answer on, e.g. vcan0 (create one with
    /// `ip link add dev vcan0 type vcan && ip link set up vcan0`).
    #[arg(long)]
    interface: String,
    /// Robot configuration file (TOML), the same as the MCM's; the embedded P-Rob2
    /// configuration when omitted.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Address of the control socket: the `sim` command (fault injection, ground truth) as JSON
    /// lines. No access control: keep it on loopback unless the network is your test bench's.
    #[arg(long, default_value = "127.0.0.1:18020")]
    control: SocketAddr,
    /// Write every frame it receives and sends to this file, in candump format.
    #[arg(long)]
    candump: Option<PathBuf>,
    /// Periods without SYNC before the arm's time goes on without the master (1 to 1000).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u64).range(1..=1000))]
    sync_grace: u64,
    /// Run the arm's loop with SCHED_FIFO at this priority (1 to 99; below the MCM's cycle,
    /// `cycle.priority`, when both share a machine). Default: normal scheduling.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=99))]
    fifo_priority: Option<u8>,
    /// Print the counters every this many seconds (0: only at the end).
    #[arg(long, default_value_t = 60)]
    summary_s: u64,
}

/// Run with `args` (the first is the program's name); the process's exit code.
pub fn main(args: impl IntoIterator<Item = OsString>) -> ExitCode {
    let args = match Args::try_parse_from(args) {
        Ok(a) => a,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let config = match &args.config {
        Some(path) => mcm_shared::config::RobotConfig::from_file(path),
        None => Ok(mcm_shared::config::RobotConfig::prob2_default()),
    };
    let config = match config {
        Ok(c) => c,
        Err(e) => {
            eprintln!("mcm-virtual-arm: {e}");
            return ExitCode::from(2);
        }
    };
    let opts = Options {
        interface: args.interface,
        config,
        control: args.control,
        candump: args.candump,
        grace: args.sync_grace,
        summary: Duration::from_secs(args.summary_s),
        fifo_priority: args.fifo_priority,
    };
    match run(&opts) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("mcm-virtual-arm: {e}");
            ExitCode::FAILURE
        }
    }
}
