//! The browser pendant (docs/web.md; default port 18014, `[gateway.web]`): a page, its assets,
//! a small JSON API and one WebSocket per page, on a port of its own.
//!
//! Connections are accepted and admitted by [`crate::transport::server`] like those of the JSON
//! and HMI ports (per-peer cap `[gateway.web] max_per_peer`, total and loopback reserve of
//! `[gateway.connections]`, eviction of the longest-idle one, never the one that controls the
//! arm). Each admitted connection speaks HTTP/1.1 ([`http`]) and is answered only when it
//! addresses one of the robot's own names ([`own_names`]); the routes are:
//! - `/` and the page's files ([`assets`], embedded in the binary);
//! - `/api/model` and `/api/flight-records[/NAME]` ([`api`]);
//! - `/ws`: the page's WebSocket ([`socket`]): the JSON protocol's commands in, their results
//!   out, through the very connection code of a TCP JSON client (same access rules and
//!   ownership), and state frames ([`frames`]) at `[gateway.web] rate_hz`, only ever the newest
//!   (a slow page skips frames; it never holds memory or the core up).
//!
//! Runs on a thread of its own with its own single-threaded tokio runtime ([`start`]), never in
//! the real-time cycle: the pages are best-effort, and their frames (ten pages: 300 messages a
//! second, sent in bursts at each frame) must not queue ahead of the machine clients' commands
//! on the gateway's workers, which also have the short scheduling slice
//! (`crate::core_link::latency`) that this thread does not ask for.

mod api;
mod arrivals;
mod assets;
pub(crate) mod frames;
mod http;
mod own_names;
mod pipe;
mod socket;

use crate::command::Context;
use crate::transport::server::{self, Port};
use std::future::Future;
use tokio::net::TcpListener;

/// Serve the pendant on `listener` (bound on the gateway's runtime) on the thread `mcm-web`,
/// until `shutdown` resolves; join the returned thread to wait for its connections' end.
pub fn start(
    listener: TcpListener,
    ctx: Context,
    instance: String,
    shutdown: impl Future + Send + 'static,
) -> std::io::Result<std::thread::JoinHandle<()>> {
    let listener = listener.into_std()?;
    std::thread::Builder::new()
        .name("mcm-web".into())
        .spawn(move || {
            let rt = match tokio::runtime::Builder::new_current_thread()
                .enable_all()
                .build()
            {
                Ok(rt) => rt,
                Err(e) => {
                    eprintln!("mcm-gateway: the browser pendant cannot run: {e}");
                    return;
                }
            };
            rt.block_on(async move {
                match TcpListener::from_std(listener) {
                    Ok(l) => run(l, ctx, instance, shutdown).await,
                    Err(e) => eprintln!("mcm-gateway: the browser pendant cannot listen: {e}"),
                }
            });
        })
}

/// Accept web connections on `listener` for MCM instance `instance` until `shutdown` resolves,
/// then stop every connection (a page's WebSocket included) and wait for them.
pub async fn run(listener: TcpListener, ctx: Context, instance: String, shutdown: impl Future) {
    let mut limits = ctx.cfg.gateway.connections.clone();
    limits.max_per_peer = ctx.cfg.gateway.web.max_per_peer;
    let frames = frames::Frames::start(&ctx);
    let bound = match listener.local_addr() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("mcm-gateway: the browser pendant cannot tell its own address: {e}");
            return;
        }
    };
    let routes = http::Routes::new(&ctx, &instance, frames, bound);
    server::run_limited(
        listener,
        ctx,
        shutdown,
        WEB_PORT,
        limits,
        move |s, c, sh, sl| http::serve(s, c, sh, sl, routes.clone()),
    )
    .await;
}

/// The web port: a refused connection gets a plain HTTP 503 with the reason.
pub const WEB_PORT: Port = Port {
    what: "web connection",
    refusal: http_refusal,
    is_local: server::admission::is_loopback,
};

#[cfg(test)]
mod tests;

/// An HTTP/1.1 503 response saying `reason`, the connection closed after it.
fn http_refusal(reason: &str) -> String {
    let body = format!("{reason}\n");
    format!(
        "HTTP/1.1 503 Service Unavailable\r\ncontent-type: text/plain; charset=utf-8\r\n\
         content-length: {}\r\nconnection: close\r\n\r\n{body}",
        body.len()
    )
}
