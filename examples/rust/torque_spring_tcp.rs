//! A torque loop over TCP: gravity compensation (by the MCM) plus a virtual spring and damper
//! that pulls one axis to a set-point a few degrees from where it starts.
//!
//! ```sh
//! cargo run --release                                           # the MCM, JSON on port 18010
//! cargo run --release -p mcm-client --bin torque_spring_tcp     # [--addr HOST:PORT] [--axis 1] [--offset 5] [--seconds 3]
//! ```
//!
//! In TORQUE_CONTROL with `gravity_compensation` the torques given by `set_torques` are added
//! to the model's gravity compensation and 70 % of its friction compensation: zero torques
//! leave the arm floating where it is, and the spring's torque `k (q0 - q) - d q'` moves only
//! the chosen axis. With `dt_status` equal to the cycle period the MCM sends every cycle's
//! state once; the torques sent in answer apply in the next cycle. The session's timeout
//! (0.1 s) brings the arm to HOLD if this program stops answering.

use clap::Parser;
use mcm_client::tcp::{Event, TcpClient, TorqueOptions};
use std::time::{Duration, Instant};

#[derive(Parser)]
struct Args {
    #[arg(long, default_value = "127.0.0.1:18010")]
    addr: String,
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
    let mut mcm = TcpClient::connect(&args.addr)?;
    let info = mcm.info()?;
    if mcm.calibrate_if_needed()? {
        println!("calibrated first");
    }
    let s = mcm.torque_control(TorqueOptions {
        timeout_s: Some(0.1),
        dt_status_s: Some(info.cycle_time),
        gravity_compensation: true,
    })?;
    let start = s.axis_states.position[i];
    let set_point = start + args.offset;
    println!(
        "axis {}: start {start:.3} deg, spring set-point {set_point:.3} deg",
        args.axis
    );
    let end = Instant::now() + Duration::from_secs_f64(args.seconds);
    let (mut ticks, mut last) = (0u64, start);
    while Instant::now() < end {
        match mcm.next_event(Duration::from_secs(1))? {
            Some(Event::Status(s)) if s.mode == mcm_client::Mode::TorqueControl => {
                ticks += 1;
                let (q, v) = (s.axis_states.position[i], s.axis_states.velocity[i]);
                last = q;
                let mut torques = [0.0; 6];
                torques[i] = K * (set_point - q).to_radians() - D * v.to_radians();
                mcm.set_torques(torques)?;
            }
            Some(Event::Status(s)) => return Err(format!("the mode changed to {}", s.mode).into()),
            Some(Event::CommandError(e)) => return Err(e.into()),
            Some(Event::SafetyError { message, .. }) => return Err(message.into()),
            Some(Event::Notice(n)) => println!("notice: {n}"),
            None => return Err("no status from the MCM for 1 s".into()),
        }
    }
    let held = mcm.hold()?;
    println!(
        "{ticks} states answered in {:.1} s; axis {} ended at {last:.3} deg ({:.3} deg from the set-point), now {}",
        args.seconds,
        args.axis,
        last - set_point,
        held.mode
    );
    Ok(())
}
