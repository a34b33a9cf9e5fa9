//! The torque loop of `torque_spring_tcp` over shared memory, at the cycle rate, with the
//! client's `control` loop: the callback gets each cycle's state and returns the next torques.
//!
//! Run it on the robot's computer (the same machine as the MCM):
//!
//! ```sh
//! cargo run --release                                           # the MCM, instance "default"
//! cargo run --release -p mcm-client --bin torque_spring_shm     # [--instance NAME] [--axis 1] [--offset 5] [--seconds 3]
//! ```
//!
//! At the end it prints the loop's summary: cycles, cycles missed, and the share of answers to
//! the state of cycle k that the core applied in cycle k + 1.

use clap::Parser;
use mcm_client::shm::{ControlOutput, ShmClient};
use mcm_client::{Mode, mcm_shared};
use mcm_shared::command::TorqueControl;

#[derive(Parser)]
struct Args {
    #[arg(long, default_value = "default")]
    instance: String,
    #[arg(long, default_value_t = 1)]
    axis: u8,
    /// Set-point relative to the start [deg].
    #[arg(long, default_value_t = 5.0, allow_negative_numbers = true)]
    offset: f64,
    #[arg(long, default_value_t = 3.0)]
    seconds: f64,
}

/// Spring [Nm/rad] and damper [Nm s/rad].
const K: f64 = 150.0;
const D: f64 = 25.0;

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let i = usize::from(args.axis.clamp(1, 6) - 1);
    let mut mcm = ShmClient::connect(&args.instance)?;
    if mcm.calibrate_if_needed()? {
        println!("calibrated first");
    }
    mcm.torque_control(TorqueControl {
        timeout_s: Some(0.1),
        gravity_compensation: true,
    })?;
    let first = mcm.wait_state()?;
    let start = first.measured_position[i];
    let set_point = start + args.offset;
    let period_s = first.timing.period_ns as f64 * 1e-9;
    let cycles = (args.seconds / period_s).round() as u64;
    println!(
        "axis {}: start {start:.3} deg, spring set-point {set_point:.3} deg, {cycles} cycles of {:.1} ms",
        args.axis,
        period_s * 1e3
    );
    let mut last = start;
    let summary = mcm.control(|s| {
        if s.seq >= first.seq + cycles {
            return ControlOutput::Finish;
        }
        let (q, v) = (s.measured_position[i], s.velocity[i]);
        last = q;
        let mut torques = [0.0; 6];
        torques[i] = K * (set_point - q).to_radians() - D * v.to_radians();
        ControlOutput::Torques(torques)
    })?;
    mcm.hold()?;
    let mode = Mode::try_from(mcm.latest().mode)?;
    println!(
        "axis {} ended at {last:.3} deg ({:.3} deg from the set-point), now {mode}",
        args.axis,
        last - set_point
    );
    println!("control loop: {summary}");
    Ok(())
}
