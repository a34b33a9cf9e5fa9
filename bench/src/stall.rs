//! Reply delivery across a gateway stall: busy clients whose commands go to the real-time core,
//! the gateway stopped (SIGSTOP) for a while and continued (SIGCONT); every request must get its
//! result, and none may be an error.

use crate::client::{Client, HOLD, INFO, READ_WAIT, is_error};
use crate::error::BenchError;
use crate::rtt::Flood;
use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Requests each client keeps unanswered on its connection.
const WINDOW: usize = 4;

/// What one client saw.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ClientCount {
    pub command: &'static str,
    pub sent: u64,
    pub ok: u64,
    pub errors: u64,
    /// Requests that got no result at all (read timed out or the connection closed).
    pub lost: u64,
    pub first_error: Option<String>,
}

/// The whole run.
#[derive(Debug, Clone)]
pub struct StallResult {
    pub clients: Vec<ClientCount>,
    /// `pvt_points` batches the flooding connections got answered.
    pub flood_batches: u64,
}

impl StallResult {
    pub fn lost(&self) -> u64 {
        self.clients.iter().map(|c| c.lost).sum()
    }
    pub fn errors(&self) -> u64 {
        self.clients.iter().map(|c| c.errors).sum()
    }
    pub fn sent(&self) -> u64 {
        self.clients.iter().map(|c| c.sent).sum()
    }
}

fn signal(pid: i32, sig: libc::c_int) -> Result<(), BenchError> {
    // SAFETY: signalling the gateway process the launcher we started reported.
    let rc = unsafe { libc::kill(pid, sig) };
    if rc == 0 {
        Ok(())
    } else {
        Err(BenchError::Setup(format!(
            "kill({pid}, {sig}) failed: {}",
            std::io::Error::last_os_error()
        )))
    }
}

fn client_loop(
    mut c: Client,
    command: &'static str,
    stop: &AtomicBool,
    answered: &AtomicU64,
) -> ClientCount {
    let json: &str = if command == "hold" { &HOLD } else { &INFO };
    let mut n = ClientCount {
        command,
        ..ClientCount::default()
    };
    let mut outstanding = 0u64;
    loop {
        while !stop.load(Ordering::Relaxed) && outstanding < WINDOW as u64 {
            if c.send(json).is_err() {
                break;
            }
            n.sent += 1;
            outstanding += 1;
        }
        if outstanding == 0 {
            return n;
        }
        match c.recv() {
            Ok(v) => {
                outstanding -= 1;
                answered.fetch_add(1, Ordering::Relaxed);
                if is_error(&v) {
                    n.errors += 1;
                    n.first_error
                        .get_or_insert_with(|| v.to_value().to_string());
                } else {
                    n.ok += 1;
                }
            }
            Err(_) => {
                n.lost += outstanding;
                return n;
            }
        }
    }
}

/// Run `clients` busy clients (half `hold`, half `info`), stop the gateway `gateway_pid` for
/// `stall` after they got going, continue it, let them go on for `after`, then stop them and
/// wait (at most the client read timeout) for every result still due.
///
/// `flood` connections send `flood_batch` (`pvt_points`) over and over meanwhile: each batch
/// is many command samples, so commands wait in the core's queue when the gateway stops and
/// the core goes on answering them during the stall, far more replies than the busy clients
/// alone have outstanding. Their results are not counted.
pub fn run(
    addr: SocketAddr,
    gateway_pid: i32,
    clients: usize,
    stall: Duration,
    after: Duration,
    flood: usize,
    flood_batch: String,
) -> Result<StallResult, BenchError> {
    let flood = Flood::start(addr, flood, flood_batch)?;
    let stop = Arc::new(AtomicBool::new(false));
    let answered = Arc::new(AtomicU64::new(0));
    let mut threads = Vec::with_capacity(clients);
    for i in 0..clients {
        let c = Client::connect(addr)?;
        c.set_read_timeout(READ_WAIT)?;
        let command = if i % 2 == 0 { "hold" } else { "info" };
        let (stop, answered) = (stop.clone(), answered.clone());
        threads.push(std::thread::spawn(move || {
            client_loop(c, command, &stop, &answered)
        }));
    }
    // Going: a few results per client before the stall.
    let deadline = Instant::now() + Duration::from_secs(10);
    while answered.load(Ordering::Relaxed) < 10 * clients as u64 && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(5));
    }
    signal(gateway_pid, libc::SIGSTOP)?;
    // The stall itself is the measured condition, not a synchronisation.
    std::thread::sleep(stall);
    signal(gateway_pid, libc::SIGCONT)?;
    let before = answered.load(Ordering::Relaxed);
    let deadline = Instant::now() + after.max(Duration::from_secs(1)) * 5;
    let resume = Instant::now();
    while (resume.elapsed() < after || answered.load(Ordering::Relaxed) < before + clients as u64)
        && Instant::now() < deadline
    {
        std::thread::sleep(Duration::from_millis(5));
    }
    stop.store(true, Ordering::Relaxed);
    let flood_batches = flood.stop()?;
    let clients = threads
        .into_iter()
        .map(|t| {
            t.join()
                .map_err(|_| BenchError::Setup("a stall client panicked".into()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(StallResult {
        clients,
        flood_batches,
    })
}
