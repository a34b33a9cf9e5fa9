//! `mcm-bench`: the benchmark of the MCM command path (see docs/performance.md, "Command path
//! benchmark"). Starts its own simulated MCM, measures, prints one table with the targets.

mod client;
mod cyclictest;
mod error;
mod loopmatch;
mod mcm;
mod phases;
mod report;
mod rtt;
mod run;
mod shm;
mod stall;
mod stats;
mod torque;
mod zmq;

use clap::Parser;
use std::path::PathBuf;

/// Benchmark of the MCM command path against the targets of its issue.
#[derive(Debug, Parser)]
#[command(name = "mcm-bench")]
pub struct Args {
    /// A short run (fewer samples, 1,000 torque-loop cycles instead of 10,000), to check that
    /// everything works; its figures are not the ones to quote.
    #[arg(long)]
    pub quick: bool,
    /// The `mcm` launcher to start (default: the one beside this binary).
    #[arg(long)]
    pub mcm: Option<PathBuf>,
    /// Robot configuration for the MCM under test (passed to `mcm --config`; default: the
    /// embedded P-Rob2 one). E.g. to raise `[gateway.connections]` limits for the flood.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Skip cyclictest (then the wake-up latency ratio is not measured).
    #[arg(long)]
    pub no_cyclictest: bool,
    /// Seconds of the wake-up latency measurement (default 10 with --quick, else 60).
    #[arg(long)]
    pub latency_secs: Option<u64>,
    /// Answers of each torque loop (default 1000 with --quick, else 10000).
    #[arg(long)]
    pub torque_cycles: Option<u64>,
    /// Connections flooding `pvt_points` during the `hold` measurement.
    #[arg(long, default_value_t = 60)]
    pub flood_clients: usize,
    /// How long the gateway is stopped (SIGSTOP) [ms].
    #[arg(long, default_value_t = 1000)]
    pub stall_ms: u64,
    /// Busy clients during the gateway stall.
    #[arg(long, default_value_t = 8)]
    pub stall_clients: usize,
    /// Connections flooding `pvt_points` during the stall (queued commands the core answers
    /// while the gateway is stopped; their results are not counted).
    #[arg(long, default_value_t = 8)]
    pub stall_flood: usize,
    /// Seconds the ZeroMQ subscribers count missed cycles (`--only zmq`; the target is 600).
    #[arg(long, default_value_t = 60)]
    pub zmq_secs: u64,
    /// Run only these phases (comma-separated: latency, status, hold, torque, stall; or zmq
    /// alone: ZeroMQ publication and the TCP round trip with and without 5 subscribers).
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
}

impl Args {
    /// Whether the phase `name` runs.
    pub fn wants(&self, name: &str) -> bool {
        self.only.is_empty() || self.only.iter().any(|p| p == name)
    }
}

fn main() {
    let args = Args::parse();
    let result = if args.only.iter().any(|p| p == "zmq") {
        zmq::run(&args)
    } else {
        run::run(&args)
    };
    match result {
        Ok(all_pass) => std::process::exit(if all_pass { 0 } else { 1 }),
        Err(e) => {
            eprintln!("mcm-bench: {e}");
            std::process::exit(2);
        }
    }
}
