//! The JSON/TCP protocol (docs/protocol.md; default port 18010): [`framing`] splits a
//! connection's bytes into commands, [`connection`] serves one client (executes its commands
//! one after the other and writes one result line each, with the spontaneous errors and notices
//! in between).

pub(crate) mod connection;
pub(crate) mod framing;

use crate::command::Context;
use crate::transport::server::{self, Port};
use mcm_shared::error_code::ErrorCode;
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
    refusal: refusal_line,
    is_local: server::admission::is_loopback,
};

/// The line that refuses a connection the port has no room for.
fn refusal_line(message: &str) -> String {
    json_line(ErrorCode::TooManyConnections, message)
}

/// A generic ERROR result line with its `code` and `message`.
pub fn json_line(code: ErrorCode, message: &str) -> String {
    format!(
        "{}\n",
        mcm_shared::protocol::json::to_ascii(&crate::command::result::error(code, message))
    )
}
