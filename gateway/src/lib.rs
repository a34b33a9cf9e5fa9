//! # mcm-gateway: the MCM's network front end
//!
//! A non-real-time tokio process that serves the JSON/TCP machine-to-machine protocol
//! (default port 18010) and passes every command through iceoryx2 shared memory to the
//! real-time core (`mcm-rt`). It never blocks the real-time side: it only reads the state
//! blackboard and publishes command samples.
//!
//! Layout (as in tokio's mini-redis): [`framing`] splits bytes into commands, [`cmd`] parses
//! and validates each command (one file per command), [`exec`] runs it through the
//! [`bridge`] to the core and builds the [`result`], [`connection`] serves one client,
//! [`server`] accepts clients and shuts them down.

pub mod args;
pub mod bridge;
pub mod cmd;
pub mod connection;
pub mod exec;
pub mod framing;
pub mod result;
pub mod server;
pub mod shutdown;

use mcm_shared::config::RobotConfig;
use mcm_shared::service::ServiceNames;
use std::net::SocketAddr;
use std::sync::Arc;

/// Default TCP port of the JSON protocol.
pub const DEFAULT_JSON_PORT: u16 = 18010;
/// Default TCP port of the text HMI.
pub const DEFAULT_HMI_PORT: u16 = 18011;

/// What the gateway serves, and where.
#[derive(Debug, Clone)]
pub struct GatewayOptions {
    pub config: RobotConfig,
    pub names: ServiceNames,
    /// Address of the JSON listener (port 0: any free port).
    pub json_addr: SocketAddr,
}

/// Starting the gateway failed.
#[derive(Debug, thiserror::Error)]
pub enum GatewayError {
    #[error("cannot listen for JSON clients on {addr}: {source}")]
    Bind {
        addr: SocketAddr,
        source: std::io::Error,
    },
}

/// Run the gateway until `shutdown` resolves. `ready` is called once with the bound addresses.
pub async fn run(
    opts: GatewayOptions,
    ready: impl FnOnce(SocketAddr),
    shutdown: impl std::future::Future,
) -> Result<(), GatewayError> {
    let listener = tokio::net::TcpListener::bind(opts.json_addr)
        .await
        .map_err(|source| GatewayError::Bind {
            addr: opts.json_addr,
            source,
        })?;
    let json_addr = listener.local_addr().map_err(|source| GatewayError::Bind {
        addr: opts.json_addr,
        source,
    })?;
    let (bridge, bridge_thread) = bridge::Bridge::start(&opts.names);
    let ctx = exec::Context {
        cfg: Arc::new(opts.config),
        bridge,
    };
    ready(json_addr);
    server::run_json(listener, ctx, shutdown).await;
    bridge_thread.stop();
    Ok(())
}
