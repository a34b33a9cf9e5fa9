//! Draw a square in the air with `move_linear`, over TCP: the TCP on four straight sides in the
//! horizontal plane through where it starts, its orientation kept; each corner checked on the
//! TCP state the MCM reports once the arm is at rest there.
//!
//! ```sh
//! cargo run --release                                      # the MCM, JSON on port 18010
//! cargo run --release -p mcm-client --bin draw_square      # [--addr HOST:PORT] [--side 0.1] [--velocity 0.1]
//! ```
//!
//! The arm must be calibrated (this example calibrates it if it is not).

use clap::Parser;
use mcm_client::mcm_shared::command::MoveLinear;
use mcm_client::tcp::{Status, TcpClient};
use std::time::Duration;

#[derive(Parser)]
struct Args {
    #[arg(long, default_value = "127.0.0.1:18010")]
    addr: String,
    /// The joint angles [deg] the square starts from (its first corner), comma-separated.
    #[arg(
        long,
        default_value = "20,30,60,-40,50,10",
        allow_negative_numbers = true,
        value_delimiter = ',',
        num_args = 6
    )]
    start: Vec<f64>,
    /// The square's side [m].
    #[arg(long, default_value_t = 0.1)]
    side: f64,
    /// The TCP's speed on each side [m/s].
    #[arg(long, default_value_t = 0.1)]
    velocity: f64,
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

/// Whether every axis is at rest (below 0.001 deg/s).
fn still(s: &Status) -> bool {
    s.axis_states.velocity.iter().all(|v| v.abs() < 1e-3)
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let start: [f64; 6] = args.start.as_slice().try_into()?;
    let mut mcm = TcpClient::connect(&args.addr)?;
    if mcm.calibrate_if_needed()? {
        println!("calibrated first");
    }
    mcm.pvt(0.01)?;
    let plan = mcm.move_all(start, 0.5)?;
    let wait = Duration::from_secs_f64(plan.max_time_to_target + 5.0);
    let at = |s: &Status| {
        (0..6)
            .map(|i| (s.axis_states.position[i] - start[i]).abs())
            .fold(0.0, f64::max)
            < 0.01
    };
    let s = mcm.wait_until("at the start", wait, |s| at(s) && still(s))?;
    let Some(tcp) = s.cartesian_state else {
        return Err("no cartesian_state: is every axis calibrated?".into());
    };
    let [x, y, z] = tcp.position;
    let d = args.side;
    println!("start corner [m]: {x:.4} {y:.4} {z:.4}");
    let corners = [[x + d, y, z], [x + d, y + d, z], [x, y + d, z], [x, y, z]];
    let mut worst = 0.0f64;
    for (i, corner) in corners.iter().enumerate() {
        let line = mcm.move_linear(MoveLinear {
            position: *corner,
            orientation: None,
            velocity: Some(args.velocity),
            acceleration: None,
        })?;
        let error = |s: &Status| {
            s.cartesian_state.as_ref().map_or(f64::INFINITY, |c| {
                (0..3)
                    .map(|k| (c.position[k] - corner[k]).abs())
                    .fold(0.0, f64::max)
            })
        };
        let wait = Duration::from_secs_f64(line.duration + 5.0);
        let s = mcm.wait_until("at the corner", wait, |s| error(s) < 1e-3 && still(s))?;
        let e = error(&s);
        worst = worst.max(e);
        println!(
            "side {}: {:.3} s, corner {corner:.4?}, error {e:.6} m",
            i + 1,
            line.duration
        );
    }
    println!("square of {d:.3} m drawn; largest corner error {worst:.6} m");
    mcm.hold()?;
    Ok(())
}
