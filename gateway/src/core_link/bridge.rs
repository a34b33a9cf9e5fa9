//! The bridge between the async gateway and the real-time core's shared memory.
//!
//! iceoryx2 ports are not `Send`, so one plain thread owns them all: it publishes the command
//! samples that connections hand it, reads the state blackboard, routes each reply in the
//! reply blocks to the connection waiting for it, and broadcasts new state and new safety
//! errors. It never waits on the real-time core: the core never waits on it either (the
//! blackboard writer and the command subscriber do not block).
//!
//! The thread sleeps in one `poll(2)` until something is to be done: the core's state event
//! (its own listener on `mcm/<i>/state-ready`, see `event.rs`), the doorbell a connection rings
//! after queueing a job (`doorbell.rs`), or a bounded timeout (open retry, staleness, reply
//! deadlines). When the event service cannot be opened while the state can (a core without
//! it), the bridge says so once on stderr and reads the state every
//! [`worker::FALLBACK_POLL`] instead.
//!
//! Samples go out one at a time, the connections taking turns, `hold` and `client_gone` ahead
//! of everything else, with the samples in flight capped below the core's command buffer (see
//! `scheduler.rs`).
//!
//! Requests travel as typed [`Request`]s; each reply routed to a request and each new safety
//! error is decoded here, once, into [`Response`] and [`SafetyError`].
//!
//! The thread is a client of the core like any co-located controller: it opens the core's
//! services, publishes and finds its replies through the client library's layer
//! ([`mcm_client::shm::ports`], [`mcm_client::shm::replies`]), the same code as
//! `mcm_client::shm::ShmClient`.
//!
//! When the core is not running (not started yet, restarting, killed), requests fail at once
//! with [`BridgeError::RtNotRunning`]; the thread keeps trying to open the services, so a
//! restarted core (or a restarted gateway) reconnects by itself. A core whose services have
//! another sample layout (built from another version) is [`BridgeError::IncompatibleLayout`].
//! A request that was published but never answered is [`BridgeError::OutcomeUnknown`]: it may
//! have been executed.

pub(crate) mod doorbell;
mod event;
mod scheduler;
mod wait;
mod worker;

#[cfg(test)]
mod tests;

pub use mcm_client::shm::{OpenError, SendError};

use iceoryx2::prelude::*;
use mcm_shared::command::{DecodeError, Request};
use mcm_shared::reply::{Response, SafetyError};
use mcm_shared::sample::StateSample;
use mcm_shared::service::ServiceNames;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;
use tokio::sync::{broadcast, oneshot, watch};

/// States a receiver of [`Bridge::subscribe_every_state`] may fall behind (0.32 s at 200 Hz).
pub const EVERY_STATE_BUFFER: usize = 64;

/// Why a published request got no reply.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum NoReply {
    #[error("within {seconds} s")]
    Timeout { seconds: f64 },
    #[error("before it stopped publishing its state")]
    CoreStopped,
    #[error("before it restarted")]
    CoreRestarted,
}

/// A request through the bridge failed, or its outcome is unknown.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BridgeError {
    #[error("the real-time core (mcm-rt, instance `{instance}`) is not running or not answering")]
    RtNotRunning { instance: String },
    #[error("cannot reach the real-time core (mcm-rt, instance `{instance}`): {error}")]
    IncompatibleLayout {
        instance: String,
        #[source]
        error: OpenError,
    },
    /// The request was published, its reply never came: it may or may not have been executed.
    #[error(
        "no reply from the real-time core {0}: the command may or may not have been executed; \
         check the state"
    )]
    OutcomeUnknown(NoReply),
    #[error("publishing the command to the real-time core failed: {0}")]
    Publish(#[source] SendError),
    /// A job without a request (a bug of the gateway: every command sends at least one).
    #[error("the command carries no request for the real-time core")]
    NoRequest,
    #[error(
        "the real-time core's answer cannot be read ({0}); mcm-rt and the gateway are from \
         different MCM versions: rebuild both from the same version"
    )]
    Undecodable(DecodeError),
    #[error("the gateway is shutting down")]
    ShuttingDown,
}

impl BridgeError {
    /// Its `error_code` ([`mcm_shared::error_code`]).
    pub fn code(&self) -> mcm_shared::error_code::ErrorCode {
        use mcm_shared::error_code::ErrorCode;
        match self {
            BridgeError::RtNotRunning { .. } | BridgeError::Publish(_) => {
                ErrorCode::CoreUnavailable
            }
            BridgeError::IncompatibleLayout { .. } | BridgeError::Undecodable(_) => {
                ErrorCode::VersionMismatch
            }
            BridgeError::OutcomeUnknown(_) => ErrorCode::OutcomeUnknown,
            BridgeError::NoRequest => ErrorCode::InternalError,
            BridgeError::ShuttingDown => ErrorCode::ShuttingDown,
        }
    }

    /// Whether the command surely was not executed (so "failed" may be said).
    pub fn surely_not_executed(&self) -> bool {
        !matches!(
            self,
            BridgeError::OutcomeUnknown(_) | BridgeError::Undecodable(_)
        )
    }
}

/// The decoded reply and the state of the cycle that produced it.
pub type Answer = (Response, Box<StateSample>);

/// A new safety violation or drive error, as seen in the state.
#[derive(Debug, Clone, PartialEq)]
pub struct SafetyEvent {
    /// The error, or why its record cannot be read (a core of another MCM version).
    pub error: Result<SafetyError, DecodeError>,
    /// The mode right after it ([`mcm_shared::mode::Mode`] as `u32`).
    pub mode: u32,
    /// The flight-recorder file the real-time core writes for it.
    pub file: std::path::PathBuf,
}

/// The requests of one command, waiting for the bridge thread.
struct Job {
    client_id: u64,
    requests: Vec<Request>,
    timeout: Duration,
    answer: oneshot::Sender<Result<Answer, BridgeError>>,
    /// Nobody waits for the answer (`client_gone`): sent even though `answer` is closed.
    fire_and_forget: bool,
}

impl Job {
    /// A stop (`hold`, `client_gone`: [`mcm_shared::mode::CommandKind::is_stop`]) goes out
    /// ahead of everything else.
    fn urgent(&self) -> bool {
        matches!(self.requests.as_slice(), [one] if one.kind().is_stop())
    }
}

/// What the async side hands the bridge thread.
enum Wake {
    Job(Job),
    Stop,
}

/// The sending side of the bridge thread's channel: every message rings the doorbell the
/// thread sleeps on.
#[derive(Clone)]
struct Waker {
    tx: std::sync::mpsc::Sender<Wake>,
    bell: Arc<doorbell::Doorbell>,
}

impl Waker {
    /// Hand `w` to the bridge thread; `Err` when it has stopped.
    fn send(&self, w: Wake) -> Result<(), ()> {
        self.tx.send(w).map_err(|_| ())?;
        self.bell.ring();
        Ok(())
    }
}

/// The async side of the bridge; cheap to clone.
#[derive(Clone)]
pub struct Bridge {
    wake: Waker,
    state: watch::Receiver<Option<Box<StateSample>>>,
    errors: broadcast::Sender<SafetyEvent>,
    every_state: broadcast::Sender<Arc<StateSample>>,
    next_client: Arc<AtomicU64>,
    instance: String,
    /// Why the core cannot be reached when that is more than "not running".
    open_error: Arc<Mutex<Option<BridgeError>>>,
}

/// Handle to stop the bridge thread.
pub struct BridgeThread {
    wake: Waker,
    handle: std::thread::JoinHandle<()>,
}

impl BridgeThread {
    pub fn stop(self) {
        let _ = self.wake.send(Wake::Stop);
        let _ = self.handle.join();
    }
}

impl Bridge {
    /// Start the bridge thread for `names`; flight-recorder files are named for `flight_dir`.
    pub fn start(names: &ServiceNames, flight_dir: &str) -> (Bridge, BridgeThread) {
        set_log_level_from_env_or(LogLevel::Error);
        let (wake_tx, wake_rx) = std::sync::mpsc::channel();
        // An eventfd fails only when the process is out of descriptors at start-up.
        let bell = Arc::new(doorbell::Doorbell::new().expect("create the bridge's doorbell"));
        let wake = Waker {
            tx: wake_tx,
            bell: bell.clone(),
        };
        let (state_tx, state_rx) = watch::channel(None);
        let (err_tx, _) = broadcast::channel(64);
        let (every_tx, _) = broadcast::channel(EVERY_STATE_BUFFER);
        let open_error = Arc::new(Mutex::new(None));
        let shared = worker::Shared {
            names: names.clone(),
            state_tx,
            errors: err_tx.clone(),
            every_state: every_tx.clone(),
            flight_dir: flight_dir.to_string(),
            bell,
            open_error: open_error.clone(),
        };
        // iceoryx2 ports are not `Send`: the thread makes its own.
        let handle = std::thread::Builder::new()
            .name("mcm-ipc-bridge".into())
            .spawn(move || worker::Worker::new(shared).run(wake_rx))
            .expect("spawn the IPC bridge thread");
        let bridge = Bridge {
            wake: wake.clone(),
            state: state_rx,
            errors: err_tx,
            every_state: every_tx,
            next_client: Arc::new(AtomicU64::new(1)),
            instance: names.instance().to_string(),
            open_error,
        };
        (bridge, BridgeThread { wake, handle })
    }

    /// A client id unique to this gateway process and connection.
    pub fn new_client_id(&self) -> u64 {
        (u64::from(std::process::id()) << 32) | self.next_client.fetch_add(1, Ordering::Relaxed)
    }

    /// Send the requests of one command for the connection `client_id` (in order; several for
    /// a `pvt_points` batch) and wait for the answer to the last one.
    pub async fn request(
        &self,
        client_id: u64,
        requests: Vec<Request>,
        timeout: Duration,
    ) -> Result<Answer, BridgeError> {
        let (tx, rx) = oneshot::channel();
        self.wake
            .send(Wake::Job(Job {
                client_id,
                requests,
                timeout,
                answer: tx,
                fire_and_forget: false,
            }))
            .map_err(|_| BridgeError::ShuttingDown)?;
        rx.await.map_err(|_| BridgeError::ShuttingDown)?
    }

    /// Tell the core that the connection `client_id` ended (fire and forget, ahead of other
    /// clients' work like `hold`). Its answer is ignored.
    pub fn client_gone(&self, client_id: u64) {
        let (tx, _) = oneshot::channel();
        let _ = self.wake.send(Wake::Job(Job {
            client_id,
            requests: vec![Request::ClientGone],
            timeout: crate::command::REPLY_TIMEOUT,
            answer: tx,
            fire_and_forget: true,
        }));
    }

    /// The newest state, if the core is running.
    pub fn latest_state(&self) -> Option<Box<StateSample>> {
        self.state.borrow().clone()
    }

    /// The client that controls the arm in the newest state (0: nobody, or no core). Read in
    /// place, without copying the state.
    pub fn owner(&self) -> u64 {
        self.state
            .borrow()
            .as_ref()
            .map_or(0, |s| s.owner_client_id)
    }

    /// Whether the newest state says the core is making its controlled stop before it exits
    /// (`STATE_SHUTTING_DOWN`).
    pub fn core_shutting_down(&self) -> bool {
        self.state
            .borrow()
            .as_ref()
            .is_some_and(|s| s.flags & mcm_shared::sample::STATE_SHUTTING_DOWN != 0)
    }

    /// The newest state; when there is none, the first one that comes within `wait` (the
    /// gateway just started and its bridge has not read the core's first state yet, or the core
    /// is restarting). `None`: still none after `wait`.
    pub async fn state_within(&self, wait: Duration) -> Option<Box<StateSample>> {
        let mut watch = self.state.clone();
        let first = tokio::time::timeout(wait, watch.wait_for(Option::is_some)).await;
        match first {
            Ok(Ok(state)) => state.clone(),
            _ => None,
        }
    }

    /// What a request gets while there is no state: the core is not running, or its services
    /// are of another layout.
    pub fn unavailable(&self) -> BridgeError {
        self.open_error
            .lock()
            .ok()
            .and_then(|e| e.clone())
            .unwrap_or_else(|| BridgeError::RtNotRunning {
                instance: self.instance.clone(),
            })
    }

    /// A receiver of state changes.
    pub fn watch_state(&self) -> watch::Receiver<Option<Box<StateSample>>> {
        self.state.clone()
    }

    /// A receiver of every new state, in order (at most [`EVERY_STATE_BUFFER`] behind; a
    /// slower receiver is told how many it lagged).
    pub fn subscribe_every_state(&self) -> broadcast::Receiver<Arc<StateSample>> {
        self.every_state.subscribe()
    }

    /// A receiver of new safety errors.
    pub fn subscribe_errors(&self) -> broadcast::Receiver<SafetyEvent> {
        self.errors.subscribe()
    }

    pub fn instance(&self) -> &str {
        &self.instance
    }
}
