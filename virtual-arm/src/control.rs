//! The virtual arm's control socket: the contract's `sim` command (fault injection and ground
//! truth, `docs/protocol.md`) over TCP, one JSON object per line, answered with the same `sim`
//! result line the MCM's gateway gives for it on the simulated robot.
//!
//! ```text
//! -> {"command":"sim","arguments":{"emergency_stop":true}}
//! <- {"result_type":"sim","true_position":[0.0,...],"true_velocity":[0.0,...],"emergency_stop":true}
//! ```
//!
//! Any other command, or a line that is not one, is answered with a `generic` error that says
//! why. Each connection has its own thread; requests reach the arm's loop through a channel
//! ([`Request`]) and it answers each before its next wait, so a request waits at most about a
//! millisecond. There is no access control: bind it to loopback (the default) unless the network
//! is the test bench's own (docs/virtual-arm.md).

use mcm_shared::config::RobotConfig;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::protocol::Command;
use mcm_shared::protocol::results::{Answer, SimResult, six};
use mcm_shared::units::rad_to_deg6;
use mcm_sim::{SimCommand, SimCommandError, SimTruth};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, Sender, SyncSender, channel, sync_channel};
use std::time::Duration;

/// The longest request line taken (bytes); a longer one closes the connection.
pub const MAX_LINE: usize = 64 * 1024;
/// Connections served at once; more are refused with an error line.
pub const MAX_CONNECTIONS: usize = 16;
/// How long a connection waits for the arm's loop to answer.
const ANSWER_WAIT: Duration = Duration::from_secs(5);

/// A fault injection (or, with no argument, a read of the truth) for the arm's loop, with where
/// to answer.
#[derive(Debug)]
pub struct Request {
    pub command: SimCommand,
    pub answer: SyncSender<Result<SimTruth, SimCommandError>>,
}

/// The control socket could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum ControlError {
    #[error("cannot listen for control connections on {address}: {source}")]
    Bind {
        address: SocketAddr,
        #[source]
        source: std::io::Error,
    },
    #[error("cannot start the control socket's thread: {0}")]
    Spawn(#[source] std::io::Error),
}

/// Listen on `address` and serve connections on threads of their own; the requests come out of
/// the returned receiver. Returns the address as bound (port 0 picks one).
pub fn serve(
    address: SocketAddr,
    cfg: RobotConfig,
) -> Result<(SocketAddr, Receiver<Request>), ControlError> {
    let listener =
        TcpListener::bind(address).map_err(|source| ControlError::Bind { address, source })?;
    let bound = listener
        .local_addr()
        .map_err(|source| ControlError::Bind { address, source })?;
    let (tx, rx) = channel();
    let cfg = Arc::new(cfg);
    std::thread::Builder::new()
        .name("control".into())
        .spawn(move || accept(listener, tx, cfg))
        .map_err(ControlError::Spawn)?;
    Ok((bound, rx))
}

fn accept(listener: TcpListener, tx: Sender<Request>, cfg: Arc<RobotConfig>) {
    let open = Arc::new(AtomicUsize::new(0));
    for stream in listener.incoming() {
        let Ok(mut stream) = stream else { continue };
        if open.fetch_add(1, Ordering::SeqCst) >= MAX_CONNECTIONS {
            open.fetch_sub(1, Ordering::SeqCst);
            let line = Answer::error(
                ErrorCode::TooManyConnections,
                format!(
                    "mcm-virtual-arm: {MAX_CONNECTIONS} control connections are open already; allowed: at most {MAX_CONNECTIONS}"
                ),
            );
            let _ = writeln!(stream, "{}", line.to_value());
            continue;
        }
        let (tx, cfg, count) = (tx.clone(), Arc::clone(&cfg), Arc::clone(&open));
        let spawned = std::thread::Builder::new()
            .name("control-conn".into())
            .spawn(move || {
                connection(stream, &tx, &cfg);
                count.fetch_sub(1, Ordering::SeqCst);
            });
        if spawned.is_err() {
            open.fetch_sub(1, Ordering::SeqCst);
        }
    }
}

fn connection(stream: TcpStream, tx: &Sender<Request>, cfg: &RobotConfig) {
    let Ok(mut out) = stream.try_clone() else {
        return;
    };
    let mut lines = BufReader::new(stream);
    let mut line = Vec::new();
    loop {
        line.clear();
        match lines
            .by_ref()
            .take(MAX_LINE as u64 + 1)
            .read_until(b'\n', &mut line)
        {
            Ok(0) | Err(_) => return,
            Ok(_) => {}
        }
        if line.len() > MAX_LINE {
            let e = Answer::error(
                ErrorCode::LineTooLong,
                format!("request line longer than {MAX_LINE} bytes; allowed: at most {MAX_LINE}"),
            );
            let _ = writeln!(out, "{}", e.to_value());
            return;
        }
        let text = String::from_utf8_lossy(&line);
        if text.trim().is_empty() {
            continue;
        }
        let answer = answer(text.trim(), tx, cfg);
        if writeln!(out, "{}", answer.to_value()).is_err() {
            return;
        }
    }
}

/// The answer to one request line.
pub fn answer(text: &str, tx: &Sender<Request>, cfg: &RobotConfig) -> Answer {
    let command = match Command::from_json(text, cfg) {
        Ok(Command::Sim(c)) => c,
        Ok(other) => {
            return Answer::error(
                ErrorCode::UnknownCommand,
                format!(
                    "mcm-virtual-arm answers only `sim` (fault injection and ground truth), not `{}`; \
                 send it to the MCM's gateway",
                    other.name()
                ),
            );
        }
        Err(e) => return Answer::error(e.code(), e.to_string()),
    };
    let (answer_tx, answer_rx) = sync_channel(1);
    let request = Request {
        command,
        answer: answer_tx,
    };
    if tx.send(request).is_err() {
        return Answer::error(ErrorCode::ShuttingDown, "mcm-virtual-arm is stopping");
    }
    match answer_rx.recv_timeout(ANSWER_WAIT) {
        Ok(Ok(truth)) => Answer::Sim(sim_result(&truth)),
        Ok(Err(e)) => {
            let words = e.to_string();
            Answer::error(mcm_shared::reply::Reason::from(e).error_code(), words)
        }
        Err(_) => Answer::error(
            ErrorCode::OutcomeUnknown,
            format!(
                "mcm-virtual-arm did not answer within {} s",
                ANSWER_WAIT.as_secs()
            ),
        ),
    }
}

/// The `sim` result for `truth` [rad, rad/s], in degrees, as the gateway writes it.
pub fn sim_result(truth: &SimTruth) -> SimResult {
    SimResult {
        true_position: six(&rad_to_deg6(&truth.position)),
        true_velocity: six(&rad_to_deg6(&truth.velocity)),
        emergency_stop: truth.emergency_stop,
    }
}

#[cfg(test)]
mod tests;
