//! The ZeroMQ interface (`[gateway.zmq]`, off by default; `mcm --zmq`): a ROUTER socket that
//! takes the same JSON commands as the JSON/TCP port and gives the same results, one reply per
//! request, every peer (routing id) a client of its own with the same ownership and access
//! rules ([`router`], [`peer`]); and a PUB socket with the state every cycle (topic `state`)
//! and every spontaneous error (topic `error`) ([`publish`]). Each socket lives in a thread of
//! its own, so neither can delay the real-time core (which never waits on the gateway anyway)
//! or the gateway's TCP clients.
//!
//! The implementation is libzmq (the `zmq` crate, which builds libzmq 4.3.4 from source):
//! `docs/performance.md` ("ZeroMQ") has the measurements that chose it.

mod message;
mod peer;
mod publish;
mod router;

use crate::command::Context;
use mcm_shared::config::ZmqConfig;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Starting the ZeroMQ interface failed.
#[derive(Debug, thiserror::Error)]
pub enum ZmqError {
    #[error("gateway.zmq.{key}: cannot bind the ZeroMQ {what} socket to {endpoint}: {source}")]
    Bind {
        key: &'static str,
        what: &'static str,
        endpoint: String,
        source: zmq::Error,
    },
    #[error("setting up the ZeroMQ interface failed ({what}): {source}")]
    Setup {
        what: &'static str,
        source: zmq::Error,
    },
    #[error("starting a thread of the ZeroMQ interface failed: {0}")]
    Thread(#[from] std::io::Error),
}

fn setup<T>(what: &'static str, r: zmq::Result<T>) -> Result<T, ZmqError> {
    r.map_err(|source| ZmqError::Setup { what, source })
}

/// The running interface: its bound endpoints and threads.
pub struct Zmq {
    /// The ROUTER's endpoint as bound (a `*` port resolved).
    pub router: String,
    /// The PUB's endpoint as bound.
    pub publish: String,
    stop: Arc<AtomicBool>,
    bell: Arc<crate::core_link::bridge::doorbell::Doorbell>,
    router_thread: std::thread::JoinHandle<()>,
    publisher: publish::Publisher,
}

/// The endpoint `socket` is bound to, a `*` port resolved (what the ready line names); an
/// endpoint libzmq cannot report (or not as UTF-8) is a setup error, not the configured text.
fn bound(socket: &zmq::Socket, what: &'static str) -> Result<String, ZmqError> {
    setup(what, socket.get_last_endpoint())?.map_err(|_| ZmqError::Setup {
        what,
        source: zmq::Error::EINVAL,
    })
}

/// Bind the sockets of `cfg` and start their threads; peers' requests run as tasks on `rt`.
pub fn start(cfg: &ZmqConfig, ctx: Context, rt: tokio::runtime::Handle) -> Result<Zmq, ZmqError> {
    let zctx = zmq::Context::new();
    let router = setup("ROUTER socket", zctx.socket(zmq::ROUTER))?;
    setup("ROUTER linger", router.set_linger(0))?;
    setup(
        "ROUTER heartbeat",
        router.set_heartbeat_ivl(router::HEARTBEAT_IVL_MS),
    )?;
    setup(
        "ROUTER heartbeat timeout",
        router.set_heartbeat_timeout(router::HEARTBEAT_TIMEOUT_MS),
    )?;
    // A request larger than this could not be a command: libzmq drops its connection.
    setup("ROUTER maxmsgsize", router.set_maxmsgsize(1 << 20))?;
    router.bind(&cfg.router).map_err(|source| ZmqError::Bind {
        key: "router",
        what: "ROUTER",
        endpoint: cfg.router.clone(),
        source,
    })?;
    // Unique per gateway process: one context each.
    let monitor_endpoint = format!("inproc://mcm-zmq-router-monitor-{}", std::process::id());
    let events = zmq::SocketEvent::ACCEPTED as i32
        | zmq::SocketEvent::DISCONNECTED as i32
        | zmq::SocketEvent::CLOSED as i32;
    setup("ROUTER monitor", router.monitor(&monitor_endpoint, events))?;
    let monitor = setup("monitor socket", zctx.socket(zmq::PAIR))?;
    setup("monitor connect", monitor.connect(&monitor_endpoint))?;

    #[cfg(not(feature = "bench-zeromq-rs"))]
    let (publisher, publish_at) = {
        let publisher = setup("PUB socket", zctx.socket(zmq::PUB))?;
        setup("PUB linger", publisher.set_linger(100))?;
        setup(
            "PUB high-water mark",
            publisher.set_sndhwm(publish::SEND_HWM),
        )?;
        publisher
            .bind(&cfg.publish)
            .map_err(|source| ZmqError::Bind {
                key: "publish",
                what: "PUB",
                endpoint: cfg.publish.clone(),
                source,
            })?;
        let at = bound(&publisher, "PUB endpoint")?;
        (
            publish::Publisher::spawn(publisher, ctx.bridge.clone())?,
            at,
        )
    };
    #[cfg(feature = "bench-zeromq-rs")]
    let (publisher, publish_at) = {
        eprintln!("mcm-gateway: comparison build: the PUB socket is the pure-Rust zeromq crate's");
        publish::Publisher::spawn_zeromq_rs(cfg.publish.clone(), ctx.bridge.clone())?
    };
    let router_at = bound(&router, "ROUTER endpoint")?;
    let bell = Arc::new(
        crate::core_link::bridge::doorbell::Doorbell::new().map_err(std::io::Error::other)?,
    );
    let (tx, replies) = std::sync::mpsc::channel();
    let stop = Arc::new(AtomicBool::new(false));
    let r = router::Router {
        socket: router,
        monitor,
        max_peers: cfg.max_peers,
        ctx,
        rt,
        out: peer::Outbox {
            tx,
            bell: bell.clone(),
        },
        replies,
        stop: stop.clone(),
    };
    let router_thread = std::thread::Builder::new()
        .name("mcm-zmq-router".into())
        .spawn(move || r.run())?;
    Ok(Zmq {
        router: router_at,
        publish: publish_at,
        stop,
        bell,
        router_thread,
        publisher,
    })
}

impl Zmq {
    /// Publish the notice about the core still due and the gateway's last `error` (call it
    /// after [`crate::core_link::lifecycle::settle`]), forget every peer (the core hears they
    /// are gone) and end the threads.
    pub fn stop(self) {
        self.stop.store(true, Ordering::Relaxed);
        self.bell.ring();
        let _ = self.router_thread.join();
        self.publisher.stop();
    }
}
