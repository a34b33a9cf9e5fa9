//! The JSON/TCP protocol (docs/protocol.md; default port 18010): [`framing`] splits a
//! connection's bytes into commands, [`connection`] serves one client (executes its commands
//! one after the other and writes one result line each, with the spontaneous errors and notices
//! in between).

pub(crate) mod connection;
pub(crate) mod framing;

use crate::command::Context;
use crate::transport::server::{self, Port};
use std::future::Future;
use tokio::net::TcpListener;

/// Accept JSON connections on `listener` until `shutdown` resolves, then tell every connection
/// to stop and wait for them.
pub async fn run(listener: TcpListener, ctx: Context, shutdown: impl Future) {
    server::run(listener, ctx, shutdown, JSON_PORT, connection::serve).await;
}

/// The JSON port: refusals as a generic ERROR result line.
pub const JSON_PORT: Port = Port {
    what: "JSON connection",
    refusal: json_line,
    is_local: server::admission::is_loopback,
};

/// A generic ERROR result line with `message`.
pub fn json_line(message: &str) -> String {
    format!(
        "{}\n",
        mcm_shared::protocol::json::to_ascii(&crate::command::result::error(message))
    )
}
