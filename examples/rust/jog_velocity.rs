//! Jog one axis in VELOCITY_CONTROL over TCP: +speed for 1 s, then -speed for 1 s, then
//! `hold`, answering every status tick (`dt_status` = one cycle) with `set_velocities`.
//!
//! Run the simulated arm in one terminal and this example in another:
//!
//! ```sh
//! cargo run --release                                       # the MCM, JSON on port 18010
//! cargo run --release -p mcm-client --bin jog_velocity      # [--addr HOST:PORT] [--axis N] [--speed DEG_S]
//! ```
//!
//! It powers the drives (`hold`), calibrates when an axis is not calibrated yet, and prints the
//! axis's start, farthest and end position. The time is the arm's own (the ticks' timestamps);
//! the MCM ramps each velocity within the axis's acceleration and jerk limits, so the axis goes
//! out by about speed x 1 s and comes back near its start.

use clap::Parser;
use mcm_client::Mode;
use mcm_client::tcp::{Event, TcpClient, VelocityOptions};
use std::time::Duration;

#[derive(Parser)]
struct Args {
    /// The MCM's JSON port.
    #[arg(long, default_value = "127.0.0.1:18010")]
    addr: String,
    /// The axis to jog, 1 to 6.
    #[arg(long, default_value_t = 1)]
    axis: u8,
    /// Its velocity [deg/s], first positive, then negative.
    #[arg(long, default_value_t = 10.0)]
    speed: f64,
    /// How long each direction lasts [s].
    #[arg(long, default_value_t = 1.0)]
    phase: f64,
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    if !(1..=6).contains(&args.axis) {
        return Err(format!("--axis {} is not allowed; expected 1 to 6", args.axis).into());
    }
    let i = usize::from(args.axis - 1);
    let mut mcm = TcpClient::connect(&args.addr)?;
    let info = mcm.info()?;
    if mcm.calibrate_if_needed()? {
        println!("calibrated first");
    }
    let s = mcm.velocity_control(VelocityOptions {
        timeout_s: Some(0.5),
        dt_status_s: Some(info.cycle_time),
    })?;
    let (t0, start) = (s.time(), s.axis_states.position[i]);
    let mut far = start;
    let mut ticks = 0u64;
    loop {
        let Some(event) = mcm.next_event(Duration::from_secs(2))? else {
            return Err("no status tick within 2 s".into());
        };
        let s = match event {
            Event::Status(s) if s.mode == Mode::VelocityControl => s,
            Event::Status(s) => return Err(format!("the mode changed to {}", s.mode).into()),
            Event::CommandError(e) => return Err(e.into()),
            Event::SafetyError { message, .. } | Event::Notice(message) => {
                return Err(message.into());
            }
        };
        let (t, q) = (s.time() - t0, s.axis_states.position[i]);
        if (q - start).abs() > (far - start).abs() {
            far = q;
        }
        if t >= 2.0 * args.phase {
            break;
        }
        let mut v = [0.0; 6];
        v[i] = if t < args.phase {
            args.speed
        } else {
            -args.speed
        };
        mcm.set_velocities(v)?;
        ticks += 1;
    }
    mcm.hold()?;
    // `hold` brings the axis to rest with the controlled stop: wait for it (bounded).
    let s = mcm.wait_until("at rest", Duration::from_secs(5), |s| {
        s.axis_states.velocity[i].abs() < 1e-3
    })?;
    println!(
        "velocity jog: {ticks} status ticks answered, axis {} at +{:.1} then -{:.1} deg/s for {:.1} s each",
        args.axis, args.speed, args.speed, args.phase
    );
    println!(
        "axis {}: start {start:.3} deg, farthest {far:.3} deg, end {:.3} deg (mode {})",
        args.axis, s.axis_states.position[i], s.mode
    );
    Ok(())
}
