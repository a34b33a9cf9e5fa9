//! The PUB socket: every state the core publishes, as the `status` result with the cycle number
//! (topic `state`), and
//! every spontaneous error, as the JSON/TCP connections get it (topic `error`: safety errors
//! and drive errors, the core shutting down or gone, the gateway stopping). Each message has
//! two frames, the topic and the JSON. Runs in its own thread (`mcm-zmq-pub`), not in the
//! cycle and not in the gateway's async workers, so publishing never delays a TCP client.
//!
//! Sending never blocks: a subscriber that does not keep up loses messages at its high-water
//! mark ([`SEND_HWM`]), nobody else notices. The thread reads every state in order from the
//! bridge ([`crate::bridge::Bridge::subscribe_every_state`]); when it falls behind by more than
//! the bridge buffers, it publishes an `error` saying how many states it skipped.

use crate::bridge::Bridge;
use crate::lifecycle::CoreWatch;
use crate::result;
use serde_json::Value;
use tokio::sync::broadcast::error::RecvError;
use tokio::sync::oneshot;

/// Messages queued per subscriber before it loses new ones (5 s of states at 200 Hz).
pub const SEND_HWM: i32 = 1000;

/// The publication thread; [`Publisher::stop`] ends it.
pub(super) struct Publisher {
    stop: oneshot::Sender<()>,
    thread: std::thread::JoinHandle<()>,
}

impl Publisher {
    /// Publish on `socket` (bound, options set) in a thread of its own.
    pub(super) fn spawn(socket: zmq::Socket, bridge: Bridge) -> std::io::Result<Publisher> {
        let (stop, stopped) = oneshot::channel();
        // Subscribed here, before the caller says the gateway is ready: no state is missed.
        let states = bridge.subscribe_every_state();
        let errors = bridge.subscribe_errors();
        let core = CoreWatch::new(bridge.watch_state());
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_time()
            .build()?;
        let thread = std::thread::Builder::new()
            .name("mcm-zmq-pub".into())
            .spawn(move || {
                crate::latency::on_thread_start();
                rt.block_on(run(socket, states, errors, core, stopped));
            })?;
        Ok(Publisher { stop, thread })
    }

    /// Publish the gateway's last `error` and end the thread.
    pub(super) fn stop(self) {
        let _ = self.stop.send(());
        let _ = self.thread.join();
    }
}

/// The `state` message: the `status` result of the state, plus `cycle`, the core's cycle
/// number (`detail.cycle` of `status`), by which a subscriber can tell that it missed none.
pub fn state_message(s: &mcm_shared::sample::StateSample) -> Value {
    let mut v = result::status(s, false);
    v["cycle"] = serde_json::json!(s.seq);
    v
}

/// Send `[topic, json]` without waiting (a full subscriber queue drops it).
fn publish(socket: &zmq::Socket, topic: &str, v: &Value) {
    let json = crate::json::to_ascii(v);
    let frames: [&[u8]; 2] = [topic.as_bytes(), json.as_bytes()];
    if let Err(e) = socket.send_multipart(frames, zmq::DONTWAIT)
        && e != zmq::Error::EAGAIN
    {
        eprintln!("mcm-gateway: publishing on the ZeroMQ PUB socket failed: {e}");
    }
}

async fn run(
    socket: zmq::Socket,
    mut states: tokio::sync::broadcast::Receiver<std::sync::Arc<mcm_shared::sample::StateSample>>,
    mut errors: tokio::sync::broadcast::Receiver<crate::bridge::SafetyEvent>,
    mut core: CoreWatch,
    mut stopped: oneshot::Receiver<()>,
) {
    loop {
        tokio::select! {
            s = states.recv() => match s {
                Ok(s) => publish(&socket, "state", &state_message(&s)),
                Err(RecvError::Lagged(n)) => publish(&socket, "error", &result::error(format!(
                    "{n} states were not published on ZeroMQ: the publisher fell behind the cycle"
                ))),
                Err(RecvError::Closed) => break,
            },
            e = errors.recv() => match e {
                Ok(ev) => publish(&socket, "error", &result::safety_event(&ev)),
                Err(RecvError::Lagged(n)) => publish(&socket, "error", &result::error(format!(
                    "{n} safety errors were not published on ZeroMQ: the publisher fell behind"
                ))),
                Err(RecvError::Closed) => break,
            },
            n = core.next() => publish(&socket, "error", &n),
            _ = &mut stopped => {
                publish(&socket, "error", &crate::lifecycle::gateway_stopping());
                break;
            }
        }
    }
}
