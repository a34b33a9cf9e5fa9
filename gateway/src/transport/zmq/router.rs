//! The ROUTER socket: takes the requests of every ZeroMQ peer, hands each peer's requests to
//! its own async task ([`super::peer`]) and sends the replies back. Runs in its own thread
//! (`mcm-zmq-router`), not in the cycle and not in the gateway's async workers: ZeroMQ sockets
//! belong to one thread, and this one sleeps in one `zmq_poll` on the socket, its monitor and
//! the doorbell the peer tasks ring when a reply is queued.
//!
//! A peer is its routing id. It is forgotten (its task ends, the core hears the client is
//! gone and ends its control, as for a closed TCP connection) when
//! - the TCP connection it last sent from closes: the socket monitor reports the connection's
//!   descriptor as disconnected (ZMTP heartbeats every [`HEARTBEAT_IVL_MS`] find a peer whose
//!   machine vanished within [`HEARTBEAT_TIMEOUT_MS`]); or
//! - it sent no request for `gateway.connections.idle_timeout_s` and runs no command.
//!
//! A request from a new peer beyond `gateway.zmq.max_peers`, or one more while
//! [`QUEUE_PER_PEER`] of the peer's requests wait, is answered at once with an ERROR result.

use super::message::Request;
use super::peer::{self, Outbox};
use crate::command::Context;
use crate::command::access::{Channel, Client};
use crate::command::result;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::protocol::results::ErrorOutcome;
use std::collections::HashMap;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use tokio::sync::mpsc;

/// Requests of one peer that may wait while it runs one.
pub const QUEUE_PER_PEER: usize = 8;
/// Interval of ZMTP heartbeats on the ROUTER's connections [ms].
pub const HEARTBEAT_IVL_MS: i32 = 1000;
/// A connection silent this long after a heartbeat is closed [ms].
pub const HEARTBEAT_TIMEOUT_MS: i32 = 5000;
/// Longest sleep of the thread (it looks for idle peers and for the stop at least this often).
const TICK: Duration = Duration::from_millis(200);
/// Most requests taken per wake-up before replies and the monitor are served again.
const BATCH: usize = 64;

/// One peer the thread knows.
struct Peer {
    requests: mpsc::Sender<Request>,
    /// The descriptor of the connection it last sent from (from the message's metadata).
    fd: Option<i32>,
    last: Instant,
    busy: Arc<AtomicBool>,
}

/// What the thread owns.
pub(super) struct Router {
    pub(super) socket: zmq::Socket,
    pub(super) monitor: zmq::Socket,
    pub(super) ctx: Context,
    pub(super) rt: tokio::runtime::Handle,
    pub(super) max_peers: usize,
    pub(super) out: Outbox,
    pub(super) replies: std::sync::mpsc::Receiver<Vec<Vec<u8>>>,
    pub(super) stop: Arc<AtomicBool>,
}

/// The peer's address from a message's metadata: the connection's descriptor names it fully;
/// else the `Peer-Address` property (its IP only); else an unspecified address.
/// The reply to a new peer when `max` peers are served already.
fn peers_full(max: usize) -> serde_json::Value {
    result::answer_error(
        ErrorOutcome::Invalid,
        ErrorCode::TooManyConnections,
        format!(
            "the gateway serves at most {max} ZeroMQ peers at once (gateway.zmq.max_peers); \
             try again when one has gone"
        ),
    )
}

/// The reply to a request of a peer whose [`QUEUE_PER_PEER`] requests wait already.
fn queue_full() -> serde_json::Value {
    result::answer_error(
        ErrorOutcome::Invalid,
        ErrorCode::TooManyRequests,
        format!(
            "{QUEUE_PER_PEER} requests of this ZeroMQ peer already wait for their replies; \
             send the next one after a reply; nothing was done"
        ),
    )
}

fn peer_address(msg: &mut zmq::Message) -> (SocketAddr, Option<i32>) {
    let fd = msg.gets("__fd").and_then(|s| s.parse::<i32>().ok());
    if let Some(addr) = fd.and_then(addr_of_fd) {
        return (addr, fd);
    }
    let ip = msg
        .gets("Peer-Address")
        .and_then(|s| s.parse::<IpAddr>().ok())
        .unwrap_or(IpAddr::V4(Ipv4Addr::UNSPECIFIED));
    (SocketAddr::new(ip, 0), fd)
}

/// The remote address of the TCP connection `fd` (owned by libzmq; only looked at).
fn addr_of_fd(fd: i32) -> Option<SocketAddr> {
    use std::os::fd::FromRawFd;
    // SAFETY: `fd` is an open TCP socket of libzmq's I/O thread (the message just came from
    // it); wrapped in ManuallyDrop, the stream never closes it, it only asks for the peer's
    // address (a read-only `getpeername`).
    let stream = std::mem::ManuallyDrop::new(unsafe { std::net::TcpStream::from_raw_fd(fd) });
    stream.peer_addr().ok()
}

impl Router {
    /// Serve until [`Router::stop`] is set; then forget every peer.
    pub(super) fn run(self) {
        crate::core_link::latency::on_thread_start();
        let mut peers: HashMap<Vec<u8>, Peer> = HashMap::new();
        let mut last_sweep = Instant::now();
        while !self.stop.load(Ordering::Relaxed) {
            let bell = self.out.bell.fd();
            let mut items = [
                self.socket.as_poll_item(zmq::POLLIN),
                self.monitor.as_poll_item(zmq::POLLIN),
                zmq::PollItem::from_fd(bell, zmq::POLLIN),
            ];
            if let Err(e) = zmq::poll(&mut items, TICK.as_millis() as i64) {
                eprintln!("mcm-gateway: waiting on the ZeroMQ ROUTER socket failed: {e}");
                std::thread::sleep(TICK);
            }
            self.out.bell.clear();
            while let Ok(frames) = self.replies.try_recv() {
                self.send(frames);
            }
            self.monitor_events(&mut peers);
            for _ in 0..BATCH {
                match self.socket.recv_msg(zmq::DONTWAIT) {
                    Ok(first) => self.take(first, &mut peers),
                    Err(_) => break,
                }
                // A connection that closed meanwhile is known before the next request.
                self.monitor_events(&mut peers);
            }
            if last_sweep.elapsed() >= TICK {
                last_sweep = Instant::now();
                self.sweep_idle(&mut peers);
            }
        }
    }

    fn send(&self, frames: Vec<Vec<u8>>) {
        // A peer gone meanwhile, or not reading (its queue full), loses the reply: the ROUTER
        // drops it and nobody waits.
        let _ = self.socket.send_multipart(frames, zmq::DONTWAIT);
    }

    /// Forget the peers of connections that closed (or whose descriptor a new connection now
    /// uses).
    fn monitor_events(&self, peers: &mut HashMap<Vec<u8>, Peer>) {
        while let Ok(frames) = self.monitor.recv_multipart(zmq::DONTWAIT) {
            let Some(head) = frames.first().filter(|h| h.len() >= 6) else {
                continue;
            };
            let event = u16::from_le_bytes([head[0], head[1]]);
            let value = i32::from_le_bytes([head[2], head[3], head[4], head[5]]);
            let closes = [
                zmq::SocketEvent::DISCONNECTED,
                zmq::SocketEvent::ACCEPTED,
                zmq::SocketEvent::CLOSED,
            ];
            if closes.iter().any(|e| e.to_raw() == event) {
                peers.retain(|_, p| p.fd != Some(value));
            }
        }
    }

    fn sweep_idle(&self, peers: &mut HashMap<Vec<u8>, Peer>) {
        let idle = Duration::from_secs_f64(self.ctx.cfg.gateway.connections.idle_timeout_s);
        peers.retain(|_, p| p.busy.load(Ordering::Relaxed) || p.last.elapsed() < idle);
    }

    /// Take one message (its first frame received) and hand it to its peer's task.
    fn take(&self, first: zmq::Message, peers: &mut HashMap<Vec<u8>, Peer>) {
        let mut frames = vec![first.to_vec()];
        let mut last = first;
        while last.get_more() {
            match self.socket.recv_msg(0) {
                Ok(m) => {
                    frames.push(m.to_vec());
                    last = m;
                }
                Err(_) => return,
            }
        }
        let Some(req) = Request::from_frames(frames) else {
            return;
        };
        let (addr, fd) = peer_address(&mut last);
        let id = req.envelope[0].clone();
        if !peers.contains_key(&id) {
            if peers.len() >= self.max_peers {
                let line = mcm_shared::protocol::json::to_ascii(&peers_full(self.max_peers));
                self.send(req.reply(line));
                return;
            }
            peers.insert(id.clone(), self.new_peer(addr));
        }
        let peer = peers.get_mut(&id).expect("inserted above");
        peer.last = Instant::now();
        peer.fd = fd.or(peer.fd);
        if let Err(e) = peer.requests.try_send(req) {
            let req = match e {
                mpsc::error::TrySendError::Full(r) | mpsc::error::TrySendError::Closed(r) => r,
            };
            self.send(req.reply(mcm_shared::protocol::json::to_ascii(&queue_full())));
        }
    }

    fn new_peer(&self, addr: SocketAddr) -> Peer {
        let (tx, rx) = mpsc::channel(QUEUE_PER_PEER);
        let busy = Arc::new(AtomicBool::new(false));
        let client = Client::new(&self.ctx.clients, &self.ctx.bridge, Channel::Zmq, addr);
        self.rt.spawn(peer::serve(
            self.ctx.clone(),
            client,
            rx,
            busy.clone(),
            self.out.clone(),
        ));
        Peer {
            requests: tx,
            fd: None,
            last: Instant::now(),
            busy,
        }
    }
}

#[cfg(test)]
mod tests;
