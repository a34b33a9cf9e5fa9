//! The bridge between the async gateway and the real-time core's shared memory.
//!
//! iceoryx2 ports are not `Send`, so one plain thread owns them all: it publishes the command
//! samples that connections hand it, polls the state blackboard every millisecond, routes each
//! reply in the state's reply ring to the connection waiting for it, and broadcasts new state
//! and new safety errors. It never waits on the real-time core: the core never waits on it
//! either (the blackboard writer and the command subscriber do not block).
//!
//! When the core is not running (not started yet, restarting, killed), requests fail at once
//! with [`BridgeError::RtNotRunning`]; the thread keeps trying to open the services, so a
//! restarted core (or a restarted gateway) reconnects by itself.

use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::reader::EntryHandle;
use iceoryx2::prelude::*;
use mcm_shared::sample::{CommandSample, ErrorRecord, Reply, StateSample};
use mcm_shared::service::{COMMAND_BUFFER, STATE_KEY, ServiceNames};
use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};
use tokio::sync::{broadcast, mpsc, oneshot, watch};

/// State older than this means the real-time core stopped.
const STALE_AFTER: Duration = Duration::from_millis(500);
/// Poll period of the blackboard.
const POLL: Duration = Duration::from_millis(1);
/// Samples published and not yet answered, at most (keeps the core's command buffer from
/// overflowing).
const MAX_IN_FLIGHT: usize = COMMAND_BUFFER / 2;
/// A published sample not answered within this time no longer counts as in flight.
const UNACKED_EXPIRY: Duration = Duration::from_secs(5);

/// A request through the bridge failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BridgeError {
    #[error("the real-time core (mcm-rt, instance `{instance}`) is not running or not answering")]
    RtNotRunning { instance: String },
    #[error("no reply from the real-time core within {seconds} s")]
    Timeout { seconds: f64 },
    #[error("publishing the command to the real-time core failed: {0}")]
    Publish(String),
    #[error("the gateway is shutting down")]
    ShuttingDown,
}

/// A reply and the state of the cycle that produced it.
pub type Answer = (Reply, Box<StateSample>);

/// A new safety violation or drive error, as seen in the state.
#[derive(Debug, Clone, PartialEq)]
pub struct SafetyEvent {
    pub record: ErrorRecord,
    /// The mode right after it ([`mcm_shared::mode::Mode`] as `u32`).
    pub mode: u32,
    /// The flight-recorder file the real-time core writes for it.
    pub file: std::path::PathBuf,
}

struct Request {
    samples: Vec<CommandSample>,
    timeout: Duration,
    answer: oneshot::Sender<Result<Answer, BridgeError>>,
}

/// The async side of the bridge; cheap to clone.
#[derive(Clone)]
pub struct Bridge {
    requests: mpsc::Sender<Request>,
    state: watch::Receiver<Option<Box<StateSample>>>,
    errors: broadcast::Sender<SafetyEvent>,
    next_client: Arc<AtomicU64>,
    instance: String,
}

/// Handle to stop the bridge thread.
pub struct BridgeThread {
    stop: Arc<AtomicBool>,
    handle: Option<std::thread::JoinHandle<()>>,
}

impl BridgeThread {
    pub fn stop(mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

impl Bridge {
    /// Start the bridge thread for `names`; flight-recorder files are named for `flight_dir`.
    pub fn start(names: &ServiceNames, flight_dir: &str) -> (Bridge, BridgeThread) {
        set_log_level_from_env_or(LogLevel::Error);
        let (req_tx, req_rx) = mpsc::channel(256);
        let (state_tx, state_rx) = watch::channel(None);
        let (err_tx, _) = broadcast::channel(64);
        let stop = Arc::new(AtomicBool::new(false));
        let worker = Worker {
            names: names.clone(),
            requests: req_rx,
            state: state_tx,
            errors: err_tx.clone(),
            flight_dir: flight_dir.to_string(),
            stop: stop.clone(),
        };
        let handle = std::thread::Builder::new()
            .name("mcm-ipc-bridge".into())
            .spawn(move || worker.run())
            .expect("spawn the IPC bridge thread");
        let bridge = Bridge {
            requests: req_tx,
            state: state_rx,
            errors: err_tx,
            next_client: Arc::new(AtomicU64::new(1)),
            instance: names.instance().to_string(),
        };
        (
            bridge,
            BridgeThread {
                stop,
                handle: Some(handle),
            },
        )
    }

    /// A client id unique to this gateway process and connection.
    pub fn new_client_id(&self) -> u64 {
        (u64::from(std::process::id()) << 32) | self.next_client.fetch_add(1, Ordering::Relaxed)
    }

    /// Send the samples of one command (with `client_id` set on each) and wait for the reply to
    /// the last one.
    pub async fn request(
        &self,
        client_id: u64,
        mut samples: Vec<CommandSample>,
        timeout: Duration,
    ) -> Result<Answer, BridgeError> {
        for s in &mut samples {
            s.client_id = client_id;
        }
        let (tx, rx) = oneshot::channel();
        self.requests
            .send(Request {
                samples,
                timeout,
                answer: tx,
            })
            .await
            .map_err(|_| BridgeError::ShuttingDown)?;
        rx.await.map_err(|_| BridgeError::ShuttingDown)?
    }

    /// The newest state, if the core is running.
    pub fn latest_state(&self) -> Option<Box<StateSample>> {
        self.state.borrow().clone()
    }

    /// A receiver of state changes.
    pub fn watch_state(&self) -> watch::Receiver<Option<Box<StateSample>>> {
        self.state.clone()
    }

    /// A receiver of new safety errors.
    pub fn subscribe_errors(&self) -> broadcast::Receiver<SafetyEvent> {
        self.errors.subscribe()
    }

    pub fn instance(&self) -> &str {
        &self.instance
    }
}

struct Ports {
    _node: Node<ipc::Service>,
    state: EntryHandle<ipc::Service, u32, StateSample>,
    publisher: Publisher<ipc::Service, CommandSample, ()>,
}

fn open_ports(names: &ServiceNames) -> Option<Ports> {
    let node = NodeBuilder::new()
        .name(&names.node("mcm-gateway").as_str().try_into().ok()?)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .ok()?;
    let state_service = node
        .service_builder(&names.state().as_str().try_into().ok()?)
        .blackboard_opener::<u32>()
        .open()
        .ok()?;
    let reader = state_service.reader_builder().create().ok()?;
    let state = reader.entry::<StateSample>(&STATE_KEY).ok()?;
    let command_service = node
        .service_builder(&names.command().as_str().try_into().ok()?)
        .publish_subscribe::<CommandSample>()
        .open()
        .ok()?;
    let publisher = command_service.publisher_builder().create().ok()?;
    Some(Ports {
        _node: node,
        state,
        publisher,
    })
}

struct Pending {
    client_id: u64,
    deadline: Instant,
    timeout: Duration,
    answer: oneshot::Sender<Result<Answer, BridgeError>>,
}

struct Worker {
    names: ServiceNames,
    requests: mpsc::Receiver<Request>,
    state: watch::Sender<Option<Box<StateSample>>>,
    errors: broadcast::Sender<SafetyEvent>,
    flight_dir: String,
    stop: Arc<AtomicBool>,
}

impl Worker {
    fn not_running(&self) -> BridgeError {
        BridgeError::RtNotRunning {
            instance: self.names.instance().to_string(),
        }
    }

    fn run(mut self) {
        let mut ports: Option<Ports> = None;
        let mut last_open_try: Option<Instant> = None;
        let mut pending: HashMap<u64, Pending> = HashMap::new();
        let mut next_request: u64 = 1;
        let mut last_seq = 0u64;
        let mut last_change = Instant::now();
        let mut alive = false;
        let mut last_reply = 0u64;
        let mut last_error_seq: Option<u64> = None;
        // Requests that wait for room in the core's command buffer, with the index of their
        // next sample to publish.
        let mut waiting: std::collections::VecDeque<(Request, usize)> = Default::default();
        // Every sample published and not answered yet, with when it was published.
        let mut unacked: HashMap<u64, Instant> = HashMap::new();

        while !self.stop.load(Ordering::Relaxed) {
            if ports.is_none()
                && last_open_try.is_none_or(|t| t.elapsed() > Duration::from_millis(100))
            {
                last_open_try = Some(Instant::now());
                ports = open_ports(&self.names);
            }

            // Read the state.
            if let Some(p) = &ports {
                let state = *p.state.get();
                if state.seq != last_seq {
                    if !alive || state.seq < last_seq {
                        // (Re)started core: replies from before are gone.
                        last_reply = state.reply_head;
                        last_error_seq = Some(state.last_error.seq);
                    }
                    last_seq = state.seq;
                    last_change = Instant::now();
                    alive = true;
                    // Route replies.
                    let oldest = state
                        .reply_head
                        .saturating_sub(mcm_shared::sample::REPLY_RING as u64 - 1)
                        .max(1);
                    let first = (last_reply + 1).max(oldest);
                    for n in first..=state.reply_head {
                        if let Some(r) = state.reply(n) {
                            unacked.remove(&r.request_id);
                            let ours = pending
                                .get(&r.request_id)
                                .is_some_and(|p| p.client_id == r.client_id);
                            if ours && let Some(p) = pending.remove(&r.request_id) {
                                let _ = p.answer.send(Ok((*r, Box::new(state))));
                            }
                        }
                    }
                    last_reply = state.reply_head;
                    if last_error_seq != Some(state.last_error.seq) {
                        last_error_seq = Some(state.last_error.seq);
                        if state.last_error.seq != 0 {
                            let _ = self.errors.send(SafetyEvent {
                                record: state.last_error,
                                mode: state.mode,
                                file: mcm_shared::sample::flight_recorder_file(
                                    &self.flight_dir,
                                    self.names.instance(),
                                    &state.last_error,
                                ),
                            });
                        }
                    }
                    self.state.send_replace(Some(Box::new(state)));
                } else if alive && last_change.elapsed() > STALE_AFTER {
                    alive = false;
                    unacked.clear();
                    self.state.send_replace(None);
                    for (_, p) in pending.drain() {
                        let _ = p.answer.send(Err(self.not_running()));
                    }
                }
            }

            // Take new requests; publish their samples while the core's buffer has room (a long
            // pvt_points batch goes out over several polls, paced by the core's answers).
            while let Ok(req) = self.requests.try_recv() {
                waiting.push_back((req, 0));
            }
            while let Some((req, next)) = waiting.front_mut() {
                if !alive {
                    let (req, _) = waiting.pop_front().expect("front exists");
                    let _ = req.answer.send(Err(self.not_running()));
                    continue;
                }
                let p = ports.as_ref().expect("alive implies ports");
                let mut failed = None;
                while *next < req.samples.len() && unacked.len() < MAX_IN_FLIGHT {
                    let mut s = req.samples[*next];
                    s.request_id = next_request;
                    next_request += 1;
                    if let Err(e) = p.publisher.send_copy(s) {
                        failed = Some(BridgeError::Publish(format!("{e:?}")));
                        break;
                    }
                    unacked.insert(s.request_id, Instant::now());
                    *next += 1;
                }
                if let Some(e) = failed {
                    let (req, _) = waiting.pop_front().expect("front exists");
                    let _ = req.answer.send(Err(e));
                    continue;
                }
                if *next < req.samples.len() {
                    break;
                }
                let (req, _) = waiting.pop_front().expect("front exists");
                pending.insert(
                    next_request - 1,
                    Pending {
                        client_id: req.samples.last().map_or(0, |s| s.client_id),
                        deadline: Instant::now() + req.timeout,
                        timeout: req.timeout,
                        answer: req.answer,
                    },
                );
            }
            // Samples whose answer never came (a lost reply) stop counting after a while.
            unacked.retain(|_, t| t.elapsed() < UNACKED_EXPIRY);

            // Time out what waited too long.
            let now = Instant::now();
            let expired: Vec<u64> = pending
                .iter()
                .filter(|(_, p)| now >= p.deadline)
                .map(|(id, _)| *id)
                .collect();
            for id in expired {
                if let Some(p) = pending.remove(&id) {
                    let _ = p.answer.send(Err(BridgeError::Timeout {
                        seconds: p.timeout.as_secs_f64(),
                    }));
                }
            }
            std::thread::sleep(POLL);
        }
        for (_, p) in pending.drain() {
            let _ = p.answer.send(Err(BridgeError::ShuttingDown));
        }
    }
}
