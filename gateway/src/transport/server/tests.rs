//! The limits of `[gateway.connections]` over real sockets on 127.0.0.1:0, with short
//! timeouts and a bridge whose real-time core is not running (`sleep` is executed by the
//! gateway, so it serves as a long-running command). Peers that must count as remote connect
//! from 127.0.0.2 to a port whose `is_local` accepts only 127.0.0.1.

use super::*;
use crate::core_link::bridge::BridgeThread;
use crate::test_support::offline_context;
use mcm_shared::config::{ConnectionLimits, RobotConfig};
use serde_json::Value;
use std::net::SocketAddr;
use tokio::net::TcpSocket;
use tokio::sync::oneshot;
use tokio::task::JoinHandle;

const WAIT: Duration = Duration::from_secs(10);

struct Server {
    addr: SocketAddr,
    table: Shared,
    stop: oneshot::Sender<()>,
    task: JoinHandle<()>,
    bridge: BridgeThread,
}

fn limits() -> ConnectionLimits {
    ConnectionLimits {
        idle_timeout_s: 30.0,
        line_timeout_s: 30.0,
        hmi_line_timeout_s: 30.0,
        ..ConnectionLimits::default()
    }
}

/// Only 127.0.0.1 is "loopback" here, so that 127.0.0.2 plays a remote peer.
fn only_127_0_0_1(ip: IpAddr) -> bool {
    ip == IpAddr::from([127, 0, 0, 1])
}

async fn start(limits: ConnectionLimits, hmi: bool) -> Server {
    let mut cfg = RobotConfig::prob2_default();
    cfg.gateway.connections = limits;
    let (ctx, thread, _) = offline_context("srv", cfg);
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let (stop, stopped) = oneshot::channel::<()>();
    let shutdown = async move {
        let _ = stopped.await;
    };
    let table = Shared::new(ctx.cfg.gateway.connections.clone());
    let t = table.clone();
    let task = if hmi {
        let port = Port {
            is_local: only_127_0_0_1,
            ..crate::transport::hmi::HMI_PORT
        };
        tokio::spawn(run_with(
            listener,
            ctx,
            shutdown,
            port,
            crate::transport::hmi::session::serve,
            t,
        ))
    } else {
        let port = Port {
            is_local: only_127_0_0_1,
            ..crate::transport::json::JSON_PORT
        };
        tokio::spawn(run_with(
            listener,
            ctx,
            shutdown,
            port,
            crate::transport::json::connection::serve,
            t,
        ))
    };
    Server {
        addr,
        table,
        stop,
        task,
        bridge: thread,
    }
}

/// A JSON-channel server with `limits`.
async fn start_json(limits: ConnectionLimits) -> Server {
    start(limits, false).await
}

/// An HMI server with `limits`.
async fn start_hmi(limits: ConnectionLimits) -> Server {
    start(limits, true).await
}

/// The test limits with at most `n` connections per address.
fn max_per_peer(n: usize) -> ConnectionLimits {
    ConnectionLimits {
        max_per_peer: n,
        ..limits()
    }
}

impl Server {
    /// Mark every connection held now busy (as a command running in the core would).
    fn make_all_busy(&self) {
        let mut t = self.table.lock();
        for id in t.ids() {
            t.update(id, true, tokio::time::Instant::now());
        }
    }

    async fn shutdown(self) {
        let _ = self.stop.send(());
        tokio::time::timeout(WAIT, self.task)
            .await
            .unwrap()
            .unwrap();
        self.bridge.stop();
    }
}

/// A raw client that keeps everything it received.
struct Client {
    stream: TcpStream,
    got: Vec<u8>,
}

impl Client {
    async fn connect(s: &Server) -> Client {
        Self::connect_from(s, "127.0.0.1").await
    }

    async fn connect_from(s: &Server, ip: &str) -> Client {
        let sock = TcpSocket::new_v4().unwrap();
        sock.bind(format!("{ip}:0").parse().unwrap()).unwrap();
        Client {
            stream: sock.connect(s.addr).await.unwrap(),
            got: Vec::new(),
        }
    }

    async fn send(&mut self, bytes: &[u8]) {
        self.stream.write_all(bytes).await.unwrap();
    }

    /// Read until `done` holds for what was received (or the peer closed); returns it as
    /// text.
    async fn until(&mut self, done: impl Fn(&str) -> bool) -> String {
        let read = async {
            let mut buf = [0u8; 4096];
            loop {
                if done(&String::from_utf8_lossy(&self.got)) {
                    return;
                }
                match self.stream.read(&mut buf).await {
                    Ok(0) | Err(_) => return,
                    Ok(n) => self.got.extend_from_slice(&buf[..n]),
                }
            }
        };
        if tokio::time::timeout(WAIT, read).await.is_err() {
            panic!(
                "no end in time; got {:?}",
                String::from_utf8_lossy(&self.got)
            );
        }
        String::from_utf8_lossy(&self.got).into_owned()
    }

    /// The next JSON line.
    async fn line(&mut self) -> Value {
        let text = self.until(|t| t.contains('\n')).await;
        let (line, rest) = text.split_once('\n').expect("a whole line");
        self.got = rest.as_bytes().to_vec();
        serde_json::from_str(line).unwrap()
    }

    /// Everything until the server closes the connection.
    async fn rest(&mut self) -> String {
        self.until(|_| false).await
    }

    /// A command and its result line (the connection is admitted once this returns).
    async fn request(&mut self, json: &str) -> Value {
        self.send(format!("{json}\n").as_bytes()).await;
        self.line().await
    }

    /// A connection from 127.0.0.1 that has been admitted (its [`NOOP`] answered).
    async fn admitted(s: &Server) -> Client {
        Self::admitted_from(s, "127.0.0.1").await
    }

    /// A connection from `ip` that has been admitted (its [`NOOP`] answered).
    async fn admitted_from(s: &Server, ip: &str) -> Client {
        let mut c = Self::connect_from(s, ip).await;
        c.request(NOOP).await;
        c
    }

    /// An HMI session from 127.0.0.1 that has shown its prompt.
    async fn prompted(s: &Server) -> Client {
        let mut c = Self::connect(s).await;
        c.until(|t| t.contains("> ")).await;
        c
    }

    /// Assert that what the server sends until it closes the connection contains `words`.
    async fn assert_closed_with(&mut self, words: &str) {
        let text = self.rest().await;
        assert!(text.contains(words), "{text}");
    }

    /// Assert that the next line says this connection was closed for a new one, starting
    /// with `prefix`, and that nothing follows it.
    async fn assert_evicted(&mut self, prefix: &str) {
        let v = self.line().await;
        let msg = error_message(&v);
        assert!(msg.starts_with(prefix), "{msg}");
        assert_eq!(v["error_code"], "evicted", "{v}");
        assert_eq!(self.rest().await, "");
    }
}

fn error_message(v: &Value) -> &str {
    assert_eq!(v["error_status"], "ERROR", "{v}");
    v["error_message"].as_str().unwrap()
}

const SLEEP_1S: &str = r#"{"command":"sleep","arguments":{"duration":1.0}}"#;
/// Longer than any test: only the shutdown ends it.
const SLEEP_LONG: &str = r#"{"command":"sleep","arguments":{"duration":600}}"#;
/// Answered by the gateway itself at once (no round trip to the core's bridge).
const NOOP: &str = r#"{"command":"sleep","arguments":{"duration":0}}"#;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn idle_connections_are_closed_but_a_long_command_is_not_idle() {
    let s = start_json(ConnectionLimits {
        idle_timeout_s: 0.4,
        ..limits()
    })
    .await;
    let mut c = Client::connect(&s).await;
    // The sleep (1 s) runs longer than the idle timeout and is answered.
    assert_eq!(c.request(SLEEP_1S).await["error_status"], "OK");
    let v = c.line().await;
    let msg = error_message(&v);
    assert!(
        msg.starts_with("idle timeout: no command for 0.4 s (gateway.connections.idle_timeout_s)"),
        "{msg}"
    );
    assert_eq!(v["error_code"], "idle_timeout", "{v}");
    assert_eq!(c.rest().await, "", "closed after the one line");
    s.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn slowloris_is_cut_by_the_line_timeout() {
    let s = start_json(ConnectionLimits {
        line_timeout_s: 0.5,
        ..limits()
    })
    .await;
    let c = Client::connect(&s).await;
    let (mut rd, mut wr) = c.stream.into_split();
    // One byte every 50 ms of a line that would take 2 s.
    let drip = tokio::spawn(async move {
        for b in br#"{"command":"status","arguments":{"detail":true}}"#
            .iter()
            .cycle()
            .take(40)
        {
            if wr.write_all(&[*b]).await.is_err() {
                return;
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    });
    let mut got = Vec::new();
    tokio::time::timeout(WAIT, rd.read_to_end(&mut got))
        .await
        .expect("closed in time")
        .ok();
    let text = String::from_utf8_lossy(&got);
    let v: Value = serde_json::from_str(text.trim_end()).expect("exactly one line");
    assert!(
        error_message(&v).starts_with("line timeout: a command line was started but not completed within 0.5 s (gateway.connections.line_timeout_s)"),
        "{v}"
    );
    assert_eq!(v["error_code"], "line_timeout", "{v}");
    drip.abort();
    s.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_per_peer_cap_evicts_the_longest_idle_connection_with_its_reason() {
    let s = start_json(max_per_peer(2)).await;
    let mut a = Client::admitted(&s).await;
    let mut b = Client::admitted(&s).await;
    // `a` is the longest idle of 127.0.0.1: the third connection displaces it.
    let mut c = Client::connect(&s).await;
    a.assert_evicted("connection closed to make room for a new one: 127.0.0.1 already has 2 connections (at most 2 per address) and this one was the longest idle").await;
    assert_eq!(c.request(NOOP).await["error_status"], "OK");
    assert_eq!(b.request(NOOP).await["error_status"], "OK");
    s.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_sleeping_connection_is_not_protected_from_eviction() {
    let s = start_json(max_per_peer(1)).await;
    let mut a = Client::connect(&s).await;
    a.send(format!("{NOOP}\n{SLEEP_LONG}\n").as_bytes()).await;
    assert_eq!(a.line().await["error_status"], "OK");
    let mut b = Client::connect(&s).await;
    a.assert_evicted("connection closed to make room for a new one")
        .await;
    assert_eq!(b.request(NOOP).await["error_status"], "OK");
    s.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_busy_peer_at_its_cap_is_refused_with_a_reason() {
    let s = start_json(max_per_peer(1)).await;
    let mut a = Client::admitted(&s).await;
    s.make_all_busy();
    let refused = Client::connect(&s).await.rest().await;
    let v: Value = serde_json::from_str(refused.trim_end()).unwrap();
    assert!(
        error_message(&v).contains("none of them is idle; try again later"),
        "{v}"
    );
    assert_eq!(v["error_code"], "too_many_connections", "{v}");
    assert_eq!(
        a.request(NOOP).await["error_status"],
        "OK",
        "a is not disturbed"
    );
    s.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_loopback_reserve_lets_a_local_operator_in_when_remote_peers_filled_the_rest() {
    let s = start_json(ConnectionLimits {
        max_connections: 3,
        loopback_reserve: 1,
        ..limits()
    })
    .await;
    // Two "remote" peers fill the remote share and keep busy.
    let mut remote = Vec::new();
    for _ in 0..2 {
        remote.push(Client::admitted_from(&s, "127.0.0.2").await);
    }
    s.make_all_busy();
    // A third remote peer is refused ...
    Client::connect_from(&s, "127.0.0.2")
        .await
        .assert_closed_with("(1 of 3 are kept for loopback)")
        .await;
    // ... while the local operator gets the reserved slot and its `hold` answered.
    let mut op = Client::connect(&s).await;
    let v = op.request(r#"{"command":"hold"}"#).await;
    assert_eq!(v["result_type"], "generic", "{v}");
    s.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn hmi_idle_and_line_timeouts_and_eviction_are_said_in_text() {
    let s = start_hmi(ConnectionLimits {
        idle_timeout_s: 1.5,
        hmi_line_timeout_s: 0.3,
        ..limits()
    })
    .await;
    let mut idle = Client::connect(&s).await;
    idle.assert_closed_with("idle timeout: no command for 1.5 s (gateway.connections.idle_timeout_s); closing the session").await;
    let mut slow = Client::prompted(&s).await;
    slow.send(b"stat").await;
    slow.assert_closed_with("line timeout: a command line was started but not completed within 0.3 s (gateway.connections.hmi_line_timeout_s)").await;
    drop((idle, slow));
    s.shutdown().await;
    let s = start_hmi(max_per_peer(2)).await;
    let mut a = Client::prompted(&s).await;
    let _b = Client::prompted(&s).await;
    let _c = Client::connect(&s).await;
    a.assert_closed_with("connection closed to make room for a new one: 127.0.0.1 already has 2")
        .await;
    s.shutdown().await;
}
