//! A page's WebSocket session: the JSON protocol over WebSocket messages, plus the state frames.
//!
//! The session runs the very connection code of a TCP JSON client
//! ([`crate::transport::json::connection::serve_stream`]) over an in-memory pipe: each text
//! message from the page is one command line into the pipe, each result line out of it is one
//! text message to the page ([`super::pipe`], where consecutive `hold`s waiting to run are one).
//! So a page is a client like any other: the same access rules,
//! ownership, refusals, mode sessions, spontaneous errors and notices, the same time limits,
//! and when the page goes (closed tab, lost network) the core hears its client is gone and
//! stops what it drove. Between the results, the newest state frame ([`super::frames`]) is sent
//! whenever one is due; a page that reads slowly skips frames. A message that is not complete
//! within `[gateway.connections] line_timeout_s` of its first byte ([`super::arrivals`]) is
//! answered like a slow JSON line (a `line_timeout` ERROR), then the socket is closed with
//! code 1008.

use super::arrivals::Arrivals;
use super::frames::Frames;
use super::pipe::pipe;
use crate::command::Context;
use crate::command::access::Channel;
use crate::transport::json::connection::serve_stream;
use crate::transport::json::json_line;
use crate::transport::server::FAREWELL_TIMEOUT;
use crate::transport::server::admission::Slot;
use crate::transport::server::timeouts::{Expiry, WRITE_TIMEOUT};
use crate::transport::shutdown::Shutdown;
use axum::extract::ws::{CloseFrame, Message, WebSocket, close_code};
use futures_util::{SinkExt, StreamExt};
use std::net::SocketAddr;
use std::time::Duration;
use tokio::sync::oneshot;

/// Serve the page's socket `ws` (from `peer`, its bytes' arrivals on `arrivals`) until the page
/// or the connection ends it.
pub async fn session(
    ws: WebSocket,
    peer: SocketAddr,
    ctx: Context,
    shutdown: Shutdown,
    slot: Slot,
    frames: Frames,
    arrivals: Arrivals,
) -> std::io::Result<()> {
    let (mut sink, mut inbox) = ws.split();
    let (page_in, reader, writer, mut page_out) = pipe(ctx.cfg.clone());
    let limits = ctx.cfg.gateway.connections.clone();
    let connection = serve_stream(reader, writer, Channel::Web, peer, ctx, shutdown, slot);
    let (cut, cut_rx) = oneshot::channel::<String>();

    // The page's messages into the connection, each one a line; its end is the connection's.
    // A message that trickles in for longer than `line_timeout_s` ends both.
    let inbound = async move {
        let line_timeout = Duration::from_secs_f64(limits.line_timeout_s);
        arrivals.message_done();
        loop {
            let msg = tokio::select! {
                msg = inbox.next() => msg,
                () = arrivals.overdue(line_timeout) => {
                    let why = Expiry::Line.message(&limits, false);
                    eprintln!("mcm-gateway: browser pendant {peer}: {why}");
                    let _ = cut.send(why);
                    break;
                }
            };
            let Some(Ok(msg)) = msg else {
                break;
            };
            arrivals.message_done();
            let bytes = match msg {
                Message::Text(t) => t.as_bytes().to_vec(),
                // Bytes are bytes to the framing: it answers what is no command.
                Message::Binary(b) => b.to_vec(),
                Message::Close(_) => break,
                Message::Ping(_) | Message::Pong(_) => continue,
            };
            if page_in.send(bytes).await.is_err() {
                break;
            }
        }
        // The connection reads what waits, then its end.
        drop(page_in);
    };
    // The connection's results and the state frames out to the page, each send bounded in
    // time (a page that takes nothing does not hold the session up).
    let outbound = async move {
        let mut states = frames.subscribe();
        let (mut cut_rx, mut cut_open) = (cut_rx, true);
        loop {
            let (msg, times) = tokio::select! {
                biased;
                why = &mut cut_rx, if cut_open => {
                    cut_open = false;
                    let Ok(why) = why else { continue };
                    let line = json_line(mcm_shared::error_code::ErrorCode::LineTimeout, &why);
                    let close = CloseFrame {
                        code: close_code::POLICY,
                        reason: "line timeout (gateway.connections.line_timeout_s)".into(),
                    };
                    let farewell = async {
                        sink.send(Message::Text(line.trim_end().into())).await?;
                        sink.send(Message::Close(Some(close))).await
                    };
                    let _ = tokio::time::timeout(FAREWELL_TIMEOUT, farewell).await;
                    return;
                }
                result = page_out.next() => match result {
                    Some((line, times)) => (line.into(), times),
                    None => break,
                },
                changed = states.changed() => {
                    if changed.is_err() {
                        break;
                    }
                    let frame = states.borrow_and_update().clone();
                    match frame {
                        Some(f) => (f, 1),
                        None => continue,
                    }
                }
            };
            // A result for coalesced `hold`s goes once for each of them.
            for _ in 0..times {
                let sent =
                    tokio::time::timeout(WRITE_TIMEOUT, sink.send(Message::Text(msg.clone())));
                if !matches!(sent.await, Ok(Ok(()))) {
                    return;
                }
            }
        }
        let _ = tokio::time::timeout(FAREWELL_TIMEOUT, sink.close()).await;
    };
    let pump = async move {
        tokio::pin!(inbound, outbound);
        tokio::select! {
            () = &mut outbound => {}
            // The page went: the connection ends on the pipe's end; its last lines still go.
            () = &mut inbound => {
                let _ = tokio::time::timeout(FAREWELL_TIMEOUT, &mut outbound).await;
            }
        }
    };
    let (ended, ()) = tokio::join!(connection, pump);
    ended
}
