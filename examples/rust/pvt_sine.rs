//! Stream a sine on one axis with `pvt_points`, over TCP, keeping the MCM's PVT queue filled.
//!
//! ```sh
//! cargo run --release                                  # the MCM, JSON on port 18010
//! cargo run --release -p mcm-client --bin pvt_sine     # [--addr HOST:PORT] [--axis 1] [--amplitude 10] [--period 2] [--cycles 2]
//! ```
//!
//! Points are 0.01 s apart (`pvt` dt). The sine starts and ends at rest at the axis's current
//! position (1 - cos shape), so the first and last points need no jump. Batches of 100 points
//! (1 s) are queued while the queue holds less than 1 s.

use clap::Parser;
use mcm_client::PvtPoint;
use mcm_client::tcp::TcpClient;
use std::f64::consts::TAU;
use std::time::Duration;

#[derive(Parser)]
struct Args {
    #[arg(long, default_value = "127.0.0.1:18010")]
    addr: String,
    #[arg(long, default_value_t = 1)]
    axis: u8,
    /// Peak-to-peak half amplitude [deg].
    #[arg(long, default_value_t = 10.0)]
    amplitude: f64,
    /// Period of one oscillation [s].
    #[arg(long, default_value_t = 2.0)]
    period: f64,
    /// Oscillations.
    #[arg(long, default_value_t = 2)]
    cycles: u32,
}

const DT: f64 = 0.01;
const BATCH: usize = 100;

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
    if mcm.calibrate_if_needed()? {
        println!("calibrated first");
    }
    let start = mcm.pvt(DT)?.axis_states.position;
    let n = (args.cycles as f64 * args.period / DT).round() as usize;
    let w = TAU / args.period;
    let points: Vec<PvtPoint> = (1..=n)
        .map(|k| {
            let t = k as f64 * DT;
            let mut p = PvtPoint {
                position_deg: start,
                velocity_deg_s: [0.0; 6],
            };
            p.position_deg[i] += args.amplitude * (1.0 - (w * t).cos());
            p.velocity_deg_s[i] = args.amplitude * w * (w * t).sin();
            p
        })
        .collect();
    let mut peak: f64 = 0.0;
    for batch in points.chunks(BATCH) {
        // Wait until the queue holds less than one batch, then queue the next.
        loop {
            let s = mcm.status_detail()?;
            peak = peak.max((s.axis_states.position[i] - start[i]).abs());
            if s.detail.is_some_and(|d| d.pvt_queue.queued < BATCH as u32) {
                break;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        mcm.pvt_points(batch)?;
    }
    // Until the stream has run out.
    loop {
        let s = mcm.status_detail()?;
        peak = peak.max((s.axis_states.position[i] - start[i]).abs());
        if s.detail.is_some_and(|d| d.pvt_queue.queued == 0) {
            let end = s.axis_states.position[i];
            println!(
                "streamed {n} points on axis {}: peak excursion {peak:.2} deg (commanded {:.2}), back at {end:.3} deg (start {:.3})",
                args.axis,
                2.0 * args.amplitude,
                start[i]
            );
            return Ok(());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}
