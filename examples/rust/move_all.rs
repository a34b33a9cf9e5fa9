//! Move all axes together with `move_all` and print the plan the MCM answers, over TCP.
//!
//! ```sh
//! cargo run --release                                  # the MCM, JSON on port 18010
//! cargo run --release -p mcm-client --bin move_all     # [--addr HOST:PORT] [--targets "0,10,20,0,0,0"] [--vf 0.5]
//! ```
//!
//! The arm must be calibrated (run `calibrate_and_move` first, or this example calibrates it).

use clap::Parser;
use mcm_client::tcp::TcpClient;
use std::time::Duration;

#[derive(Parser)]
struct Args {
    #[arg(long, default_value = "127.0.0.1:18010")]
    addr: String,
    /// Six targets [deg], comma-separated.
    #[arg(
        long,
        default_value = "0,10,20,0,0,0",
        allow_negative_numbers = true,
        value_delimiter = ',',
        num_args = 6
    )]
    targets: Vec<f64>,
    /// Share of the axes' maximum velocity and acceleration, above 0 and at most 1.
    #[arg(long, default_value_t = 0.5)]
    vf: f64,
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let targets: [f64; 6] = args.targets.as_slice().try_into()?;
    let mut mcm = TcpClient::connect(&args.addr)?;
    if mcm.calibrate_if_needed()? {
        println!("calibrated first");
    }
    mcm.pvt(0.01)?;
    let plan = mcm.move_all(targets, args.vf)?;
    println!(
        "move_all planned: longest axis {}, {:.3} s to the target, peak velocities {:?} deg/s",
        plan.longest, plan.max_time_to_target, plan.velocities
    );
    // The plan says when the arm arrives; wait for that, with a margin, until it is within
    // 0.01 deg of every target and at rest (below 0.001 deg/s).
    let distance = |s: &mcm_client::tcp::Status| {
        (0..6)
            .map(|i| (s.axis_states.position[i] - targets[i]).abs())
            .fold(0.0, f64::max)
    };
    let wait = Duration::from_secs_f64(plan.max_time_to_target + 5.0);
    let s = mcm.wait_until("at the targets", wait, |s| {
        distance(s) < 0.01 && s.axis_states.velocity.iter().all(|v| v.abs() < 1e-3)
    })?;
    println!(
        "arrived: positions {:?} deg (largest distance to the target {:.4} deg)",
        s.axis_states.position,
        distance(&s)
    );
    Ok(())
}
