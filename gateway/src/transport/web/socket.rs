//! A page's WebSocket session: the JSON protocol over WebSocket messages, plus the state frames.
//!
//! The session runs the very connection code of a TCP JSON client
//! ([`crate::transport::json::connection::serve_stream`]) over an in-memory pipe: each text
//! message from the page is one command line into the pipe, each result line out of it is one
//! text message to the page. So a page is a client like any other: the same access rules,
//! ownership, refusals, mode sessions, spontaneous errors and notices, the same time limits,
//! and when the page goes (closed tab, lost network) the core hears its client is gone and
//! stops what it drove. Between the results, the newest state frame ([`super::frames`]) is sent
//! whenever one is due; a page that reads slowly skips frames.

use super::frames::Frames;
use crate::command::Context;
use crate::command::access::Channel;
use crate::transport::json::connection::serve_stream;
use crate::transport::server::FAREWELL_TIMEOUT;
use crate::transport::server::admission::Slot;
use crate::transport::server::timeouts::WRITE_TIMEOUT;
use crate::transport::shutdown::Shutdown;
use axum::extract::ws::{Message, WebSocket};
use futures_util::{SinkExt, StreamExt};
use std::net::SocketAddr;
use tokio::io::{AsyncBufReadExt, AsyncWriteExt, BufReader};

/// Bytes the pipe between the socket and the connection code holds each way.
const PIPE_BYTES: usize = 2 * mcm_shared::protocol::MAX_COMMAND_BYTES;

/// Serve the page's socket `ws` (from `peer`) until the page or the connection ends it.
pub async fn session(
    ws: WebSocket,
    peer: SocketAddr,
    ctx: Context,
    shutdown: Shutdown,
    slot: Slot,
    frames: Frames,
) -> std::io::Result<()> {
    let (mut sink, mut inbox) = ws.split();
    let (ours, theirs) = tokio::io::duplex(PIPE_BYTES);
    let (their_rd, their_wr) = tokio::io::split(theirs);
    let connection = serve_stream(their_rd, their_wr, Channel::Web, peer, ctx, shutdown, slot);
    let (our_rd, mut our_wr) = tokio::io::split(ours);
    let mut results = BufReader::new(our_rd).lines();

    // The page's messages into the connection, each one a line; its end is the connection's.
    let inbound = async move {
        while let Some(Ok(msg)) = inbox.next().await {
            let bytes = match msg {
                Message::Text(t) => t.as_bytes().to_vec(),
                // Bytes are bytes to the framing: it answers what is no command.
                Message::Binary(b) => b.to_vec(),
                Message::Close(_) => break,
                Message::Ping(_) | Message::Pong(_) => continue,
            };
            if our_wr.write_all(&bytes).await.is_err() || our_wr.write_all(b"\n").await.is_err() {
                break;
            }
        }
        let _ = our_wr.shutdown().await;
    };
    // The connection's results and the state frames out to the page, each send bounded in
    // time (a page that takes nothing does not hold the session up).
    let outbound = async move {
        let mut states = frames.subscribe();
        loop {
            let msg = tokio::select! {
                line = results.next_line() => match line {
                    Ok(Some(l)) => l.into(),
                    _ => break,
                },
                changed = states.changed() => {
                    if changed.is_err() {
                        break;
                    }
                    let frame = states.borrow_and_update().clone();
                    match frame {
                        Some(f) => f,
                        None => continue,
                    }
                }
            };
            let sent = tokio::time::timeout(WRITE_TIMEOUT, sink.send(Message::Text(msg)));
            if !matches!(sent.await, Ok(Ok(()))) {
                return;
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
