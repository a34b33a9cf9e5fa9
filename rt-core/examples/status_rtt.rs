//! Round trip of a command over the JSON protocol, measured from a client process. `status` is
//! answered by the gateway from the newest state the real-time core published, without waiting
//! for a cycle: its round trip is the loopback TCP and the gateway's work (tens of
//! microseconds). Any other command (e.g. `{"command":"hold"}`) goes by shared memory to the
//! core, which serves it in its next cycle and publishes the reply with that cycle's state:
//! about one period when requests go back to back. Not a test (it asserts nothing about
//! speed); the figures go to `docs/performance.md`.
//!
//! ```sh
//! cargo run --release -- --instance perf1 --json-port 0 --hmi-port 0   # prints json=ADDR
//! cargo run --release -p mcm-rt-core --example status_rtt -- ADDR [REQUESTS] [COMMAND]
//! ```
//!
//! `REQUESTS` (default 1000) requests go one after the other on one connection, after 50
//! unmeasured ones; `COMMAND` defaults to `{"command":"status"}`.

use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

const WARM_UP: usize = 50;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let addr = args
        .next()
        .ok_or("usage: status_rtt ADDR [REQUESTS] [COMMAND] (ADDR: the json= address of mcm)")?;
    let n: usize = match args.next() {
        Some(s) => s
            .parse()
            .map_err(|e| format!("REQUESTS = {s:?} is not a count: {e}"))?,
        None => 1000,
    };
    if n == 0 {
        return Err("REQUESTS must be at least 1".into());
    }
    let command = args
        .next()
        .unwrap_or_else(|| r#"{"command":"status"}"#.to_string());
    let line = format!("{command}\n");

    let stream = TcpStream::connect(&addr).map_err(|e| format!("connect to {addr}: {e}"))?;
    stream.set_nodelay(true)?;
    stream.set_read_timeout(Some(Duration::from_secs(10)))?;
    let mut writer = stream.try_clone()?;
    let mut reader = BufReader::new(stream);
    let mut reply = String::new();
    let mut round_trip = || -> Result<Duration, Box<dyn std::error::Error>> {
        reply.clear();
        let t = Instant::now();
        writer.write_all(line.as_bytes())?;
        if reader.read_line(&mut reply)? == 0 {
            return Err("the server closed the connection".into());
        }
        let dt = t.elapsed();
        if !reply.starts_with('{') || reply.contains("\"error_status\":\"ERROR\"") {
            return Err(format!("unexpected reply: {reply}").into());
        }
        Ok(dt)
    };
    for _ in 0..WARM_UP {
        round_trip()?;
    }
    let mut us: Vec<f64> = (0..n)
        .map(|_| round_trip().map(|d| d.as_secs_f64() * 1e6))
        .collect::<Result<_, _>>()?;
    us.sort_by(f64::total_cmp);
    let pct = |p: f64| us[((us.len() - 1) as f64 * p).round() as usize];
    let mean = us.iter().sum::<f64>() / us.len() as f64;
    println!(
        "{n} x {command} on one connection to {addr}: \
         p50 {:.0} us, p90 {:.0} us, p99 {:.0} us, max {:.0} us, mean {mean:.0} us",
        pct(0.5),
        pct(0.9),
        pct(0.99),
        pct(1.0)
    );
    Ok(())
}
