//! One ZeroMQ peer (routing id) as a client of the gateway: an async task that executes its
//! requests one after the other, with the same command handling, ownership and access rules as
//! a JSON/TCP connection ([`crate::command::access::run_command`]), and hands each reply to the
//! ROUTER thread. Runs in the gateway's async tasks, not in the cycle.
//!
//! The task ends when the ROUTER thread forgets the peer (its connection closed, or it was idle
//! too long); its [`Client`] is then dropped, so the core hears the client is gone and ends its
//! control exactly as for a closed TCP connection.

use super::message::{self, Request};
use crate::command::Context;
use crate::command::access::{Client, run_command};
use crate::command::result;
use crate::core_link::bridge::doorbell::Doorbell;
use crate::transport::json::connection::{Step, decide};
use mcm_shared::error_code::ErrorCode;
use mcm_shared::protocol::results::{Answer, ErrorOutcome};
use serde_json::Value;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use tokio::sync::mpsc;

/// Where replies go: the ROUTER thread's queue and the doorbell it sleeps on.
#[derive(Clone)]
pub(super) struct Outbox {
    pub(super) tx: std::sync::mpsc::Sender<Vec<Vec<u8>>>,
    pub(super) bell: Arc<Doorbell>,
}

impl Outbox {
    /// Queue the frames of one reply and wake the ROUTER thread.
    pub(super) fn send(&self, frames: Vec<Vec<u8>>) {
        if self.tx.send(frames).is_ok() {
            self.bell.ring();
        }
    }
}

/// The reply to one request body: the command's result, or the ERROR result saying why it was
/// refused. A command that has no result on the TCP port (a successful `set_torques` or
/// `set_velocities`) gets the OK result: every request has exactly one reply.
pub async fn answer(ctx: &Context, client: &Client, body: &[u8]) -> Value {
    match decide(message::frame(body), &ctx.cfg).await {
        Step::Run(cmd) => run_command(ctx, client, &cmd)
            .await
            .result
            .unwrap_or_else(Answer::ok)
            .to_value(),
        Step::Reply(v) | Step::Close(v) => v,
        // A message has no connection to close: refused like any line that is not a command.
        Step::Foreign(kind) => result::answer_error(
            ErrorOutcome::Invalid,
            ErrorCode::InvalidJson,
            format!(
                "the message is {}, not a JSON command like {{\"command\":\"status\"}}; \
                 nothing was done",
                kind.words()
            ),
        ),
    }
}

/// Serve the peer's requests until the ROUTER thread drops its sender. `busy` is set while a
/// command runs (a running command keeps the peer from being dropped as idle).
pub(super) async fn serve(
    ctx: Context,
    client: Client,
    mut requests: mpsc::Receiver<Request>,
    busy: Arc<AtomicBool>,
    out: Outbox,
) {
    while let Some(req) = requests.recv().await {
        busy.store(true, Ordering::Relaxed);
        let reply = answer(&ctx, &client, &req.body).await;
        busy.store(false, Ordering::Relaxed);
        out.send(req.reply(mcm_shared::protocol::json::to_ascii(&reply)));
    }
    // `client` is dropped here: the core hears that this client is gone.
}
