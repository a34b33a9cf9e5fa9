//! # mcm-gateway: the MCM's network front end
//!
//! A non-real-time tokio process that serves the JSON/TCP machine-to-machine protocol
//! (default port 18010) and passes every command through iceoryx2 shared memory to the
//! real-time core (`mcm-rt`). It never blocks the real-time side: it only reads the state
//! blackboard and publishes command samples.
//!
//! Layout (as in tokio's mini-redis), by role:
//! - `transport`: how clients reach the gateway. `transport::json` is the JSON/TCP protocol
//!   (`transport::json::framing` splits bytes into commands, `transport::json::connection`
//!   serves one client), `transport::hmi` the telnet text HMI, `transport::zmq` the optional
//!   ZeroMQ interface (commands over a ROUTER socket, state and errors over a PUB socket);
//!   `transport::server` accepts and admits the TCP connections and shuts them down.
//! - `mcm_shared::protocol` parses and validates each command (one file per command, shared
//!   with the clients).
//! - `command`: executes a command under the access rules (`command::access`) and builds its
//!   typed result (`command::result` writes it as JSON).
//! - `core_link`: the link to the real-time core: the `core_link::bridge` thread that owns
//!   the shared memory, the notices about the core's life (`core_link::lifecycle`), the
//!   scheduling hint of the threads that answer clients (`core_link::latency`).
//! - [`cli`]: the command line (the crate's one public module, for the `mcm-gateway` binary
//!   and the `mcm` launcher), and `run`, which starts it all and stops it.

pub mod cli;
mod command;
mod core_link;
#[cfg(test)]
mod test_support;
mod transport;

use mcm_shared::config::RobotConfig;
use mcm_shared::service::ServiceNames;
use std::net::SocketAddr;
use std::sync::Arc;

/// Default TCP port of the JSON protocol.
pub(crate) const DEFAULT_JSON_PORT: u16 = 18010;
/// Default TCP port of the text HMI.
pub(crate) const DEFAULT_HMI_PORT: u16 = 18011;
/// Default TCP port of the browser pendant.
pub(crate) const DEFAULT_WEB_PORT: u16 = 18014;

/// What the gateway serves, and where.
#[derive(Debug, Clone)]
pub(crate) struct GatewayOptions {
    pub config: RobotConfig,
    pub names: ServiceNames,
    /// Address of the JSON listener (port 0: any free port).
    pub json_addr: SocketAddr,
    /// Address of the telnet HMI listener (port 0: any free port).
    pub hmi_addr: SocketAddr,
    /// Address of the browser pendant's listener (port 0: any free port), when
    /// `[gateway.web]` is enabled.
    pub web_addr: SocketAddr,
    /// Accept `sim` commands from other hosts than this one (`--allow-remote-sim`).
    pub allow_remote_sim: bool,
}

/// Starting the gateway failed.
#[derive(Debug, thiserror::Error)]
pub(crate) enum GatewayError {
    #[error("cannot listen on {addr}: {source}")]
    Bind {
        addr: SocketAddr,
        source: std::io::Error,
    },
    #[error(transparent)]
    Access(#[from] command::access::AccessError),
    #[error(transparent)]
    Zmq(#[from] transport::zmq::ZmqError),
    #[error("cannot start the browser pendant's thread: {0}")]
    Web(std::io::Error),
}

/// Where the gateway serves, once it does.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Ready {
    pub json: SocketAddr,
    pub hmi: SocketAddr,
    /// The browser pendant's address as bound, when `[gateway.web]` is enabled.
    pub web: Option<SocketAddr>,
    /// The ZeroMQ ROUTER and PUB endpoints as bound, when `[gateway.zmq]` is enabled.
    pub zmq: Option<(String, String)>,
}

async fn bind(addr: SocketAddr) -> Result<(tokio::net::TcpListener, SocketAddr), GatewayError> {
    let listener = tokio::net::TcpListener::bind(addr)
        .await
        .map_err(|source| GatewayError::Bind { addr, source })?;
    let local = listener
        .local_addr()
        .map_err(|source| GatewayError::Bind { addr, source })?;
    Ok((listener, local))
}

/// How long the gateway waits for the core's first state before it says it is ready anyway.
pub const READY_STATE_WAIT: std::time::Duration = std::time::Duration::from_secs(2);

/// Run the gateway until `shutdown` resolves. `ready` is called once with the bound addresses
/// of the JSON and the HMI listeners and the ZeroMQ endpoints.
pub(crate) async fn run(
    opts: GatewayOptions,
    ready: impl FnOnce(Ready),
    shutdown: impl std::future::Future,
) -> Result<(), GatewayError> {
    let access =
        command::access::Access::from_config(&opts.config.gateway.access, opts.allow_remote_sim)?;
    let (json, json_addr) = bind(opts.json_addr).await?;
    let (hmi, hmi_addr) = bind(opts.hmi_addr).await?;
    let web = if opts.config.gateway.web.enabled {
        Some(bind(opts.web_addr).await?)
    } else {
        None
    };
    let (bridge, bridge_thread) =
        core_link::bridge::Bridge::start(&opts.names, &opts.config.safety.flight_recorder_dir);
    let zmq_cfg = opts.config.gateway.zmq.clone();
    let ctx = command::Context::new(Arc::new(opts.config), bridge, access);
    let zmq = if zmq_cfg.enabled {
        let started =
            transport::zmq::start(&zmq_cfg, ctx.clone(), tokio::runtime::Handle::current());
        match started {
            Ok(z) => Some(z),
            Err(e) => {
                bridge_thread.stop();
                return Err(e.into());
            }
        }
    } else {
        None
    };
    let (stop_tx, _) = tokio::sync::broadcast::channel::<()>(1);
    let stopped = |tx: &tokio::sync::broadcast::Sender<()>| {
        let mut rx = tx.subscribe();
        async move {
            let _ = rx.recv().await;
        }
    };
    // Before any task serves: a failure to start leaves nothing running.
    let web_addr = web.as_ref().map(|(_, a)| *a);
    let web_task = match web {
        Some((listener, _)) => {
            let instance = opts.names.instance().to_string();
            let thread = transport::web::start(listener, ctx.clone(), instance, stopped(&stop_tx));
            match thread {
                Ok(t) => Some(t),
                Err(e) => {
                    if let Some(z) = zmq {
                        let _ = tokio::task::spawn_blocking(move || z.stop()).await;
                    }
                    bridge_thread.stop();
                    return Err(GatewayError::Web(e));
                }
            }
        }
        None => None,
    };
    let json_task = tokio::spawn(transport::json::run(json, ctx.clone(), stopped(&stop_tx)));
    let bridge = ctx.bridge.clone();
    let reaper = tokio::spawn(command::access::reaper::run(bridge.clone()));
    let hmi_task = tokio::spawn(transport::hmi::run(hmi, ctx, stopped(&stop_tx)));
    // Ready once the bridge holds the core's first state, so that a client's first `status`
    // right after the ready line finds it: on a slow machine opening the core's services took
    // longer than the `status` grace (`command::STATE_GRACE`), and a test's first `status`
    // was told the core was not running. Without a core (the gateway started alone), ready
    // after `READY_STATE_WAIT`; the listeners already serve meanwhile.
    let _ = bridge.state_within(READY_STATE_WAIT).await;
    ready(Ready {
        json: json_addr,
        hmi: hmi_addr,
        web: web_addr,
        zmq: zmq.as_ref().map(|z| (z.router.clone(), z.publish.clone())),
    });
    shutdown.await;
    // Usually the gateway is stopped because the core stopped: know that before any client is
    // told the gateway stops, so that every client (TCP, HMI, ZeroMQ) hears about the core
    // first (`core_link::lifecycle`). Once, for every transport: at most `SETTLE_WAIT`, so
    // that the goodbyes still fit in the launcher's stop timeout.
    core_link::lifecycle::settle(bridge.watch_state()).await;
    if let Some(z) = zmq {
        // Blocking joins (bounded: the threads wake within 200 ms), off the async workers.
        let _ = tokio::task::spawn_blocking(move || z.stop()).await;
    }
    let _ = stop_tx.send(());
    let _ = json_task.await;
    let _ = hmi_task.await;
    if let Some(t) = web_task {
        // A blocking join (bounded: its connections stop as the others do), off the workers.
        let _ = tokio::task::spawn_blocking(move || t.join()).await;
    }
    reaper.abort();
    bridge_thread.stop();
    Ok(())
}
