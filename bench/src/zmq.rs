//! `mcm-bench --only zmq`: the ZeroMQ interface against its targets (docs/performance.md,
//! "ZeroMQ"): state publication with no missed cycle for subscribers on the same machine over
//! `--zmq-secs`, and the TCP clients' `status` round trip unchanged by 5 subscribers. Starts
//! its own MCM with the ZeroMQ interface on free loopback ports; the subscribers are libzmq
//! SUB sockets, each in a thread of its own, judging misses on the core's cycle numbers.

use crate::Args;
use crate::client::{Client, STATUS};
use crate::error::BenchError;
use crate::mcm::{Mcm, locate};
use crate::stats::Summary;
use std::time::{Duration, Instant};

/// Subscribers during the second round-trip measurement (the target's number).
const SUBSCRIBERS: usize = 5;

/// What one subscriber saw.
#[derive(Debug, Default, Clone)]
struct Seen {
    samples: u64,
    missed: u64,
    /// Largest jump of the cycle number between two samples.
    max_gap: u64,
    /// The cycles missed (the first [`MISSED_KEPT`]).
    missing: Vec<u64>,
}

/// Missed cycle numbers kept per subscriber, to tell misses before the PUB socket (every
/// subscriber misses the same cycle) from messages the PUB dropped for one subscriber.
const MISSED_KEPT: usize = 100_000;

/// CPU time the process `pid` used so far (user + system) [s], from `/proc/PID/stat`.
fn cpu_seconds(pid: i32) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // After the command name in parentheses: state is field 3, utime 14, stime 15.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    // SAFETY: sysconf only reads a system constant.
    let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64;
    Some(ticks / hz)
}

/// Seconds of the gateway's CPU measurement without TCP traffic.
const IDLE_SECS: u64 = 5;

/// The gateway's CPU use over [`IDLE_SECS`] with no TCP request [% of one core].
fn idle_cpu(pid: i32) -> Option<f64> {
    let (a, t) = (cpu_seconds(pid)?, Instant::now());
    std::thread::sleep(Duration::from_secs(IDLE_SECS));
    Some(100.0 * (cpu_seconds(pid)? - a) / t.elapsed().as_secs_f64())
}

fn free_port() -> Result<u16, BenchError> {
    let l = std::net::TcpListener::bind("127.0.0.1:0")
        .map_err(|e| BenchError::Setup(format!("no free port on 127.0.0.1: {e}")))?;
    Ok(l.local_addr()
        .map_err(|e| BenchError::Setup(e.to_string()))?
        .port())
}

/// The cycle number of a `state` message (`"cycle":N`).
fn cycle_of(json: &[u8]) -> Option<u64> {
    let text = std::str::from_utf8(json).ok()?;
    let at = text.find("\"cycle\":")? + "\"cycle\":".len();
    let digits: String = text[at..]
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    digits.parse().ok()
}

/// Subscribe to `state` on `endpoint` for `secs` seconds (from its first sample).
fn subscribe(endpoint: String, secs: u64) -> std::thread::JoinHandle<Result<Seen, String>> {
    std::thread::spawn(move || {
        let ctx = zmq::Context::new();
        let sub = ctx.socket(zmq::SUB).map_err(|e| e.to_string())?;
        sub.set_rcvtimeo(2000).map_err(|e| e.to_string())?;
        sub.connect(&endpoint).map_err(|e| e.to_string())?;
        sub.set_subscribe(b"state").map_err(|e| e.to_string())?;
        let mut seen = Seen::default();
        let mut last: Option<u64> = None;
        let mut until: Option<Instant> = None;
        while until.is_none_or(|u| Instant::now() < u) {
            let frames = sub
                .recv_multipart(0)
                .map_err(|e| format!("no state within 2 s: {e}"))?;
            let cycle = frames
                .get(1)
                .and_then(|j| cycle_of(j))
                .ok_or("a state message without a cycle number")?;
            if let Some(l) = last {
                let gap = cycle.saturating_sub(l);
                seen.missed += gap.saturating_sub(1);
                for c in l + 1..cycle {
                    if seen.missing.len() < MISSED_KEPT {
                        seen.missing.push(c);
                    }
                }
                seen.max_gap = seen.max_gap.max(gap);
            }
            last = Some(cycle);
            seen.samples += 1;
            until.get_or_insert_with(|| Instant::now() + Duration::from_secs(secs));
        }
        Ok(seen)
    })
}

/// Sequential `status` round trips over TCP for `secs` seconds.
fn round_trips(c: &mut Client, secs: u64) -> Result<Summary, BenchError> {
    let mut rtt = Vec::new();
    let end = Instant::now() + Duration::from_secs(secs);
    while Instant::now() < end {
        let t = Instant::now();
        c.ok(&STATUS)?;
        rtt.push(t.elapsed());
    }
    Summary::of(&rtt).ok_or_else(|| BenchError::Setup("no round trip measured".into()))
}

/// Run the ZeroMQ benchmark; `Ok(true)` when both targets passed.
pub fn run(args: &Args) -> Result<bool, BenchError> {
    let binary = locate(args.mcm.as_deref())?;
    let instance = format!("bench-zmq-{}", std::process::id());
    let router = format!("tcp://127.0.0.1:{}", free_port()?);
    let publish = format!("tcp://127.0.0.1:{}", free_port()?);
    let more = [
        "--zmq-router",
        router.as_str(),
        "--zmq-publish",
        publish.as_str(),
    ];
    let mcm = Mcm::start_with(&binary, &instance, args.config.as_deref(), &more)?;
    let rtt_secs = if args.quick { 5 } else { 20 };
    let secs = if args.quick { 10 } else { args.zmq_secs };
    let mut c = Client::connect(mcm.json)?;
    c.wait_status("a first state", Duration::from_secs(20), |_| true)?;

    eprintln!("mcm-bench: TCP status round trips, no ZeroMQ subscriber ({rtt_secs} s)");
    let alone = round_trips(&mut c, rtt_secs)?;
    let cpu_alone = idle_cpu(mcm.gateway_pid);
    eprintln!(
        "mcm-bench: {SUBSCRIBERS} ZeroMQ subscribers for {secs} s, TCP round trips meanwhile"
    );
    let subs: Vec<_> = (0..SUBSCRIBERS)
        .map(|_| subscribe(publish.clone(), secs))
        .collect();
    // Round trips all the while every subscriber receives.
    std::thread::sleep(Duration::from_millis(500));
    let with = round_trips(&mut c, secs.saturating_sub(1 + IDLE_SECS).max(1))?;
    let cpu_with = idle_cpu(mcm.gateway_pid);
    let seen: Vec<Seen> = subs
        .into_iter()
        .map(|h| {
            h.join()
                .map_err(|_| BenchError::Setup("a subscriber thread panicked".into()))?
                .map_err(|e| BenchError::Setup(format!("subscriber: {e}")))
        })
        .collect::<Result<_, _>>()?;
    mcm.stop();

    let missed: u64 = seen.iter().map(|s| s.missed).sum();
    // Cycles every subscriber missed never reached the PUB socket (the gateway did not see
    // that state); the others were dropped on the way to one subscriber.
    let everyone: Vec<u64> = seen[0]
        .missing
        .iter()
        .copied()
        .filter(|c| seen.iter().all(|s| s.missing.binary_search(c).is_ok()))
        .collect();
    let p99_ratio = with.p99_us / alone.p99_us;
    println!(
        "ZeroMQ benchmark of {}, {secs} s per subscriber",
        binary.display()
    );
    println!("| measurement | value | target |");
    println!("| --- | --- | --- |");
    for (i, s) in seen.iter().enumerate() {
        println!(
            "| subscriber {}: samples, missed cycles, largest gap | {}, {}, {} | 0 missed |",
            i + 1,
            s.samples,
            s.missed,
            s.max_gap
        );
    }
    println!(
        "| cycles missed by every subscriber (never published: the gateway did not see them) | {} | |",
        everyone.len()
    );
    println!(
        "| messages dropped for single subscribers (PUB or subscriber) | {} | |",
        missed - everyone.len() as u64 * seen.len() as u64
    );
    println!(
        "| TCP status RTT p50 / p99 / max, no subscriber [us] | {:.0} / {:.0} / {:.0} | |",
        alone.p50_us, alone.p99_us, alone.max_us
    );
    println!(
        "| TCP status RTT p50 / p99 / max, {SUBSCRIBERS} subscribers [us] | {:.0} / {:.0} / {:.0} | not delayed |",
        with.p50_us, with.p99_us, with.max_us
    );
    let pct = |c: Option<f64>| c.map_or("?".to_string(), |c| format!("{c:.1}"));
    println!(
        "| gateway CPU, no TCP request (one core = 100 %), without / with {SUBSCRIBERS} subscribers | {} / {} | |",
        pct(cpu_alone),
        pct(cpu_with)
    );
    // "Not delayed": p99 within 1.5 times (and 200 us) of the run without subscribers.
    let not_delayed = with.p99_us <= (1.5 * alone.p99_us).max(alone.p99_us + 200.0);
    println!(
        "verdict: missed cycles {missed} ({}), RTT p99 ratio {p99_ratio:.2} ({})",
        if missed == 0 { "PASS" } else { "FAIL" },
        if not_delayed { "PASS" } else { "FAIL" }
    );
    Ok(missed == 0 && not_delayed)
}
