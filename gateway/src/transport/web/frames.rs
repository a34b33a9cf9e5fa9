//! The state frames of the pages' WebSockets: `[gateway.web] rate_hz` times a second, one task
//! takes the newest state the core published, writes it once as a frame and hands the same
//! text to every page ([`Frames::subscribe`]; a clone of it is a reference count, not a copy).
//! A page that is slow to take frames only ever gets the newest one (a `watch` channel): it skips frames and holds no memory. With no page
//! open nothing is built.
//!
//! A frame is `{"stream":"state","cycle_unix_ms":…,"owner":…,"status":…}` (docs/web.md):
//! `status` is the `status` result with detail, exactly as the JSON protocol writes it, less
//! `detail.access` and `detail.control` (they depend on the connection: a page asks with
//! `status` itself); `owner` names the client that controls the arm (or `null`);
//! `cycle_unix_ms` is the wall-clock time of the cycle that measured the state, for the page's
//! own latency figure.

use crate::command::Context;
use crate::command::result::status;
use axum::extract::ws::Utf8Bytes;
use serde_json::{Value, json};
use std::time::{Duration, SystemTime, UNIX_EPOCH};
use tokio::sync::watch;

/// The newest frame, shared by every page; cheap to clone.
#[derive(Clone)]
pub struct Frames {
    rx: watch::Receiver<Option<Utf8Bytes>>,
}

impl Frames {
    /// Start the task that writes the frames of `ctx`'s bridge; it ends when the last
    /// [`Frames`] is dropped.
    pub fn start(ctx: &Context) -> Frames {
        let (tx, rx) = watch::channel(None);
        let period = Duration::from_secs_f64(1.0 / f64::from(ctx.cfg.gateway.web.rate_hz));
        tokio::spawn(produce(ctx.clone(), tx, period));
        Frames { rx }
    }

    /// A receiver of the frames from now on.
    pub fn subscribe(&self) -> watch::Receiver<Option<Utf8Bytes>> {
        let mut rx = self.rx.clone();
        rx.mark_unchanged();
        rx
    }
}

async fn produce(ctx: Context, tx: watch::Sender<Option<Utf8Bytes>>, period: Duration) {
    let mut tick = tokio::time::interval(period);
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    let mut last_seq = None;
    loop {
        tick.tick().await;
        if tx.is_closed() {
            return;
        }
        // Only the `Frames` kept by the routes: no page is open.
        if tx.receiver_count() <= 1 {
            continue;
        }
        let Some(state) = ctx.bridge.latest_state() else {
            continue;
        };
        if last_seq == Some(state.seq) {
            continue;
        }
        last_seq = Some(state.seq);
        let frame = frame(&ctx, &state, unix_ms_of(state.t_ns));
        tx.send_replace(Some(Utf8Bytes::from(frame.to_string())));
    }
}

/// The frame of `state`, measured at wall-clock `cycle_unix_ms`.
pub fn frame(ctx: &Context, state: &mcm_shared::sample::StateSample, cycle_unix_ms: f64) -> Value {
    let owner = state.owner_client_id;
    json!({
        "stream": "state",
        "cycle_unix_ms": cycle_unix_ms,
        "owner": (owner != 0).then(|| ctx.clients.who(owner)),
        "status": status(state, true),
    })
}

/// The wall-clock time [ms since the Unix epoch] of the `CLOCK_MONOTONIC` time `t_ns`.
fn unix_ms_of(t_ns: u64) -> f64 {
    let now_unix = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64() * 1e3);
    let age_ms = mcm_client::monotonic_ns().saturating_sub(t_ns) as f64 / 1e6;
    now_unix - age_ms
}
