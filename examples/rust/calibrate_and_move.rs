//! Calibrate the arm and move one axis, over TCP (the JSON protocol).
//!
//! Run the simulated arm in one terminal and this example in another:
//!
//! ```sh
//! cargo run --release                                            # the MCM, JSON on port 18010
//! cargo run --release -p mcm-client --bin calibrate_and_move     # [--addr HOST:PORT] [--axis N] [--target DEG]
//! ```
//!
//! It powers the drives (`hold`), calibrates when an axis is not calibrated yet (about 12 s on
//! the simulated P-Rob2), enters PVT, moves the axis and waits until it has arrived.

use clap::Parser;
use mcm_client::tcp::TcpClient;
use std::time::{Duration, Instant};

#[derive(Parser)]
struct Args {
    /// The MCM's JSON port.
    #[arg(long, default_value = "127.0.0.1:18010")]
    addr: String,
    /// The axis to move, 1 to 6.
    #[arg(long, default_value_t = 1)]
    axis: u8,
    /// Its target [deg].
    #[arg(long, default_value_t = 20.0, allow_negative_numbers = true)]
    target: f64,
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let mut mcm = TcpClient::connect(&args.addr)?;
    let info = mcm.info()?;
    println!(
        "connected to {} (MCM {}, cycle {} s)",
        info.robot, info.version, info.cycle_time
    );
    let t = Instant::now();
    if mcm.calibrate_if_needed()? {
        println!("calibrated in {:.1} s", t.elapsed().as_secs_f64());
    } else {
        println!("already calibrated");
    }
    mcm.pvt(0.01)?;
    mcm.move_axis(args.axis, args.target, 0.5)?;
    println!("moving axis {} to {:.3} deg", args.axis, args.target);
    let i = usize::from(args.axis - 1);
    let s = mcm.wait_until("arrived", Duration::from_secs(20), |s| {
        let (q, v) = (s.axis_states.position[i], s.axis_states.velocity[i]);
        (q - args.target).abs() < 0.01 && v.abs() < 1e-6
    })?;
    println!(
        "axis {} at {:.3} deg (mode {})",
        args.axis, s.axis_states.position[i], s.mode
    );
    Ok(())
}
