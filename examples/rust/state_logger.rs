//! Log the state of every cycle to a CSV file, over shared memory, with `wait_state()`.
//!
//! Run it on the robot's computer (the same machine as the MCM):
//!
//! ```sh
//! cargo run --release                                       # the MCM, instance "default"
//! cargo run --release -p mcm-client --bin state_logger      # [--instance NAME] [--cycles 400] [--out state.csv]
//! ```
//!
//! One row per cycle: the cycle number, its time, the mode, and per axis the position, the
//! velocity and the motor current. It reports the cycles it missed (none when the machine
//! keeps up with the cycle rate).

use clap::Parser;
use mcm_client::shm::ShmClient;
use mcm_client::{Mode, NUM_AXES};
use std::io::Write;

#[derive(Parser)]
struct Args {
    #[arg(long, default_value = "default")]
    instance: String,
    /// States to log.
    #[arg(long, default_value_t = 400)]
    cycles: u64,
    /// The CSV file.
    #[arg(long, default_value = "state.csv")]
    out: std::path::PathBuf,
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let mut mcm = ShmClient::connect(&args.instance)?;
    let mut out = std::io::BufWriter::new(std::fs::File::create(&args.out)?);
    write!(out, "seq,t_s,mode")?;
    for what in ["position_deg", "velocity_deg_s", "current_a"] {
        for a in 1..=NUM_AXES {
            write!(out, ",{what}_{a}")?;
        }
    }
    writeln!(out)?;
    let missed_before = mcm.missed_states();
    let (mut first, mut last) = (None, 0);
    for _ in 0..args.cycles {
        let s = mcm.wait_state()?;
        first.get_or_insert(s.seq);
        last = s.seq;
        let mode = Mode::try_from(s.mode).map_or("?", Mode::as_str);
        write!(out, "{},{:.6},{mode}", s.seq, s.t_ns as f64 * 1e-9)?;
        for v in [&s.position, &s.velocity, &s.current] {
            for x in v {
                write!(out, ",{x:.6}")?;
            }
        }
        writeln!(out)?;
    }
    out.flush()?;
    println!(
        "wrote {} rows (cycles {} to {last}) to {}; missed {} cycles",
        args.cycles,
        first.unwrap_or(0),
        args.out.display(),
        mcm.missed_states() - missed_before
    );
    Ok(())
}
