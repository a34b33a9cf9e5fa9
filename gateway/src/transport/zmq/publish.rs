//! The PUB socket: every state the core publishes, as the `status` result with the cycle number
//! (topic `state`), and every spontaneous error, as the JSON/TCP connections get it (topic
//! `error`: safety errors and drive errors, the core shutting down or gone, the gateway
//! stopping; on shutdown, the notice about the core still due before the gateway's own, as on
//! TCP). Each message has two frames, the topic and the JSON. Runs in its own thread (`mcm-zmq-pub`), not in the
//! cycle and not in the gateway's async workers, so publishing never delays a TCP client.
//!
//! Sending never blocks: a subscriber that does not keep up loses messages at its high-water
//! mark ([`SEND_HWM`]), nobody else notices. The thread reads every state in order from the
//! bridge ([`crate::core_link::bridge::Bridge::subscribe_every_state`]); when it falls behind
//! by more than the bridge buffers, it publishes an `error` saying how many states it skipped.

use crate::command::result;
use crate::core_link::bridge::Bridge;
use crate::core_link::lifecycle::CoreWatch;
use mcm_shared::protocol::results::Answer;
use serde_json::Value;
use tokio::sync::broadcast::error::RecvError;
use tokio::sync::oneshot;

/// Messages queued per subscriber before it loses new ones (5 s of states at 200 Hz).
#[cfg_attr(feature = "bench-zeromq-rs", allow(dead_code))]
pub const SEND_HWM: i32 = 1000;

/// The publication thread; [`Publisher::stop`] ends it.
pub(super) struct Publisher {
    stop: oneshot::Sender<()>,
    thread: std::thread::JoinHandle<()>,
}

impl Publisher {
    /// Publish on `socket` (bound, options set) in a thread of its own.
    #[cfg_attr(feature = "bench-zeromq-rs", allow(dead_code))]
    pub(super) fn spawn(socket: zmq::Socket, bridge: Bridge) -> std::io::Result<Publisher> {
        Self::spawn_sink(move || async move { Ok(Sink::Libzmq(socket)) }, bridge).map(|(p, _)| p)
    }

    /// The comparison build (`--features mcm-gateway/bench-zeromq-rs`): publish with the
    /// pure-Rust `zeromq` crate, bound to `endpoint` in the publication thread's runtime (its
    /// connection tasks run there too, as libzmq's run in its own I/O thread). Returns the
    /// endpoint as bound.
    #[cfg(feature = "bench-zeromq-rs")]
    pub(super) fn spawn_zeromq_rs(
        endpoint: String,
        bridge: Bridge,
    ) -> std::io::Result<(Publisher, String)> {
        use zeromq::Socket as _;
        let bind = move || async move {
            let mut socket = zeromq::PubSocket::new();
            let bound = socket
                .bind(&endpoint)
                .await
                .map_err(|e| std::io::Error::other(format!("zeromq bind {endpoint}: {e}")))?;
            Ok(Sink::Rust(socket, bound.to_string()))
        };
        Self::spawn_sink(bind, bridge).map(|(p, bound)| (p, bound.unwrap_or_default()))
    }

    /// Make the sink with `make` inside the publication thread (with its runtime entered) and
    /// publish on it; the endpoint the sink reports as bound, if any.
    fn spawn_sink<F, Fut>(make: F, bridge: Bridge) -> std::io::Result<(Publisher, Option<String>)>
    where
        F: FnOnce() -> Fut + Send + 'static,
        Fut: std::future::Future<Output = std::io::Result<Sink>>,
    {
        let (stop, stopped) = oneshot::channel();
        // Subscribed here, before the caller says the gateway is ready: no state is missed.
        let states = bridge.subscribe_every_state();
        let errors = bridge.subscribe_errors();
        let core = CoreWatch::new(bridge.watch_state());
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()?;
        let (made_tx, made_rx) = std::sync::mpsc::channel();
        let thread = std::thread::Builder::new()
            .name("mcm-zmq-pub".into())
            .spawn(move || {
                crate::core_link::latency::on_thread_start();
                let sink = match rt.block_on(make()) {
                    Ok(sink) => {
                        let _ = made_tx.send(Ok(sink.bound()));
                        sink
                    }
                    Err(e) => {
                        let _ = made_tx.send(Err(e));
                        return;
                    }
                };
                rt.block_on(run(sink, states, errors, core, stopped));
            })?;
        let bound = made_rx
            .recv()
            .map_err(|_| std::io::Error::other("the publication thread ended at start"))??;
        Ok((Publisher { stop, thread }, bound))
    }

    /// Publish the notice about the core still due and the gateway's last `error`, and end
    /// the thread.
    pub(super) fn stop(self) {
        let _ = self.stop.send(());
        let _ = self.thread.join();
    }
}

/// Where the messages go.
pub(super) enum Sink {
    #[cfg_attr(feature = "bench-zeromq-rs", allow(dead_code))]
    Libzmq(zmq::Socket),
    /// The pure-Rust `zeromq` crate's PUB (comparison build only), and its bound endpoint.
    #[cfg(feature = "bench-zeromq-rs")]
    Rust(zeromq::PubSocket, String),
}

impl Sink {
    fn bound(&self) -> Option<String> {
        match self {
            Sink::Libzmq(_) => None,
            #[cfg(feature = "bench-zeromq-rs")]
            Sink::Rust(_, e) => Some(e.clone()),
        }
    }

    /// Send `[topic, json]` without waiting (a full subscriber queue drops it).
    async fn publish(&mut self, topic: &str, v: &Value) {
        let json = mcm_shared::protocol::json::to_ascii(v);
        match self {
            Sink::Libzmq(socket) => {
                let frames: [&[u8]; 2] = [topic.as_bytes(), json.as_bytes()];
                if let Err(e) = socket.send_multipart(frames, zmq::DONTWAIT)
                    && e != zmq::Error::EAGAIN
                {
                    eprintln!("mcm-gateway: publishing on the ZeroMQ PUB socket failed: {e}");
                }
            }
            #[cfg(feature = "bench-zeromq-rs")]
            Sink::Rust(socket, _) => {
                use zeromq::SocketSend as _;
                let mut msg = zeromq::ZmqMessage::from(topic.to_string());
                msg.push_back(json.into_bytes().into());
                if let Err(e) = socket.send(msg).await {
                    eprintln!("mcm-gateway: publishing with the zeromq crate failed: {e}");
                }
            }
        }
    }
}

/// The message of a new state, with its topic: on `state`, the `status` result of the state
/// plus `cycle`, the core's cycle number (`detail.cycle` of `status`), by which a subscriber
/// can tell that it missed none. A state that is no status (a core of another MCM version) is
/// an ERROR result on `error`, without `cycle`: it is no state message.
pub fn state_message(s: &mcm_shared::sample::StateSample) -> (&'static str, Value) {
    match result::status_answer("status", s, false) {
        status @ Answer::Status(_) => {
            let mut v = status.to_value();
            v["cycle"] = serde_json::json!(s.seq);
            ("state", v)
        }
        error => ("error", error.to_value()),
    }
}

async fn run(
    mut sink: Sink,
    mut states: tokio::sync::broadcast::Receiver<std::sync::Arc<mcm_shared::sample::StateSample>>,
    mut errors: tokio::sync::broadcast::Receiver<crate::core_link::bridge::SafetyEvent>,
    mut core: CoreWatch,
    mut stopped: oneshot::Receiver<()>,
) {
    loop {
        let (topic, v) = tokio::select! {
            s = states.recv() => match s {
                Ok(s) => state_message(&s),
                Err(RecvError::Lagged(n)) => ("error", result::error(mcm_shared::error_code::ErrorCode::EventsLost, format!(
                    "{n} states were not published on ZeroMQ: the publisher fell behind the cycle"
                ))),
                Err(RecvError::Closed) => break,
            },
            e = errors.recv() => match e {
                Ok(ev) => ("error", result::safety_event(&ev)),
                Err(RecvError::Lagged(n)) => ("error", result::error(mcm_shared::error_code::ErrorCode::EventsLost, format!(
                    "{n} safety errors were not published on ZeroMQ: the publisher fell behind"
                ))),
                Err(RecvError::Closed) => break,
            },
            n = core.next() => ("error", n.result()),
            _ = &mut stopped => {
                // The notice about the core still due (the gateway settled what it knows of
                // the core before it stopped this thread), then the gateway's own.
                for n in core.last_words() {
                    sink.publish("error", &n.result()).await;
                }
                break;
            }
        };
        sink.publish(topic, &v).await;
    }
}

#[cfg(test)]
mod tests;
