//! Round trips over TCP: `status` one at a time and pipelined on one connection, and the
//! `hold` acknowledgement, idle and while other connections flood `pvt_points` batches.

use crate::client::{Client, HOLD, STATUS, is_error, status_of};
use crate::error::BenchError;
use crate::stats::Summary;
use mcm_shared::protocol::results::Answer;
use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Requests sent before measuring (connection and caches warm).
pub const WARM_UP: usize = 20;
/// Most requests a pipelined client keeps unanswered on its connection.
const PIPELINE_WINDOW: usize = 32;

/// Round trips of one command sent one at a time.
#[derive(Debug, Clone)]
pub struct Sequential {
    pub summary: Option<Summary>,
    pub errors: u64,
    /// Results per second (one at a time).
    pub rate: f64,
    /// For results that carry the state's `time` (a status): from the start of the cycle that
    /// answered to reading the result, on the same clock (`CLOCK_MONOTONIC`): the part of the
    /// round trip spent after the core's answer.
    pub after_cycle: Option<Summary>,
}

/// `CLOCK_MONOTONIC` now [s], the clock of the state's `time`.
pub fn monotonic_s() -> f64 {
    // SAFETY: clock_gettime writes only the timespec passed to it.
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// The time from the start of the answering cycle (`time` of a status result, seconds on
/// `CLOCK_MONOTONIC`) to `read_at_s`; `None` for a result without a time.
pub fn after_cycle(a: &Answer, read_at_s: f64) -> Option<Duration> {
    let t = status_of(a)?.time();
    Some(Duration::from_secs_f64((read_at_s - t).max(0.0)))
}

/// Send `json` `warm_up` times unmeasured, then `count` times one after the other (each when
/// the previous result arrived), stopping early after `budget`; the time from writing the
/// command to reading its result (its line read, before it is parsed).
pub fn sequential(
    c: &mut Client,
    json: &str,
    count: usize,
    budget: Duration,
    warm_up: usize,
) -> Result<Sequential, BenchError> {
    for _ in 0..warm_up {
        c.request(json)?;
    }
    let mut samples = Vec::with_capacity(count);
    let mut after = Vec::with_capacity(count);
    let mut errors = 0;
    let start = Instant::now();
    while samples.len() < count && start.elapsed() < budget {
        let t0 = Instant::now();
        let v = c.request(json)?;
        let read_at = monotonic_s() - c.read_at().elapsed().as_secs_f64();
        samples.push(c.read_at() - t0);
        after.extend(after_cycle(&v, read_at));
        if is_error(&v) {
            errors += 1;
        }
    }
    let rate = samples.len() as f64 / start.elapsed().as_secs_f64();
    Ok(Sequential {
        summary: Summary::of(&samples),
        errors,
        rate,
        after_cycle: Summary::of(&after),
    })
}

/// Pipelined `status`: results per second and the round trip of each request.
#[derive(Debug, Clone)]
pub struct Pipelined {
    pub summary: Option<Summary>,
    pub rate: f64,
    pub errors: u64,
}

/// Keep up to [`PIPELINE_WINDOW`] `status` requests unanswered on one connection, `count` in
/// all (or until `budget` has passed; the ones sent are still read).
pub fn pipelined(c: &mut Client, count: usize, budget: Duration) -> Result<Pipelined, BenchError> {
    let mut sent_at = std::collections::VecDeque::with_capacity(PIPELINE_WINDOW);
    let mut samples = Vec::with_capacity(count);
    let mut errors = 0;
    let mut sent = 0;
    let start = Instant::now();
    loop {
        while sent < count && sent_at.len() < PIPELINE_WINDOW && start.elapsed() < budget {
            c.send(&STATUS)?;
            sent_at.push_back(Instant::now());
            sent += 1;
        }
        let Some(t0) = sent_at.pop_front() else { break };
        let v = c.recv()?;
        samples.push(c.read_at() - t0);
        if status_of(&v).is_none() {
            errors += 1;
        }
    }
    let rate = samples.len() as f64 / start.elapsed().as_secs_f64();
    Ok(Pipelined {
        summary: Summary::of(&samples),
        rate,
        errors,
    })
}

/// A flood of `pvt_points` batches from many connections, each sending a 1000-point batch and
/// reading its result, again and again, until stopped.
pub struct Flood {
    stop: Arc<AtomicBool>,
    batches: Arc<AtomicU64>,
    sockets: Vec<std::net::TcpStream>,
    threads: Vec<std::thread::JoinHandle<Result<(), BenchError>>>,
}

/// One `pvt_points` line of `points` points at `position` cut to whole degrees (towards zero) (valid
/// numbers; the mode decides). Whole degrees keep a 1000-point batch below the gateway's
/// 64 KiB command limit.
pub fn pvt_batch(points: usize, position: [f64; 6]) -> String {
    let p = format!(
        "{{\"position\":[{}],\"velocity\":[0,0,0,0,0,0]}}",
        position.map(|x| format!("{:.0}", x.trunc())).join(",")
    );
    let list = vec![p; points].join(",");
    format!("{{\"command\":\"pvt_points\",\"arguments\":{{\"points\":[{list}]}}}}")
}

impl Flood {
    pub fn start(addr: SocketAddr, clients: usize, batch: String) -> Result<Flood, BenchError> {
        let stop = Arc::new(AtomicBool::new(false));
        let batches = Arc::new(AtomicU64::new(0));
        let batch = Arc::new(batch);
        let mut threads = Vec::with_capacity(clients);
        let mut sockets = Vec::with_capacity(clients);
        for _ in 0..clients {
            let mut c = Client::connect(addr)?;
            sockets.push(c.socket()?);
            let (stop, batches, batch) = (stop.clone(), batches.clone(), batch.clone());
            threads.push(std::thread::spawn(move || {
                while !stop.load(Ordering::Relaxed) {
                    match c.request(&batch) {
                        Ok(_) => batches.fetch_add(1, Ordering::Relaxed),
                        // Stopping shuts the socket down under a waiting request.
                        Err(_) if stop.load(Ordering::Relaxed) => break,
                        Err(e) => return Err(e),
                    };
                }
                Ok(())
            }));
        }
        Ok(Flood {
            stop,
            batches,
            sockets,
            threads,
        })
    }

    pub fn batches(&self) -> u64 {
        self.batches.load(Ordering::Relaxed)
    }

    /// Stop every flooding client (closing its connection under a waiting batch); the
    /// batches answered.
    pub fn stop(self) -> Result<u64, BenchError> {
        self.stop.store(true, Ordering::Relaxed);
        for s in &self.sockets {
            let _ = s.shutdown(std::net::Shutdown::Both);
        }
        for t in self.threads {
            t.join()
                .map_err(|_| BenchError::Setup("a flooding client panicked".into()))??;
        }
        Ok(self.batches.load(Ordering::Relaxed))
    }
}

/// `hold` acknowledgement while `flood` runs: wait until the flood is under way first.
pub fn hold_under_flood(
    addr: SocketAddr,
    flood: &Flood,
    count: usize,
    budget: Duration,
) -> Result<Sequential, BenchError> {
    let deadline = Instant::now() + Duration::from_secs(10);
    while flood.batches() < 10 && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(10));
    }
    let mut c = Client::connect(addr)?;
    // No warm-up: under the flood every request may take seconds.
    sequential(&mut c, &HOLD, count, budget, 0)
}

#[cfg(test)]
mod tests;
