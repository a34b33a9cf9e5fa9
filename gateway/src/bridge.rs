//! The bridge between the async gateway and the real-time core's shared memory.
//!
//! iceoryx2 ports are not `Send`, so one plain thread owns them all: it publishes the command
//! samples that connections hand it, polls the state blackboard every millisecond, routes each
//! reply in the state's reply ring to the connection waiting for it, and broadcasts new state
//! and new safety errors. It never waits on the real-time core: the core never waits on it
//! either (the blackboard writer and the command subscriber do not block).
//!
//! Requests travel as typed [`Request`]s, encoded here; each reply routed to a request and each
//! new safety error is decoded here, once, into [`Response`] and [`SafetyError`].
//!
//! When the core is not running (not started yet, restarting, killed), requests fail at once
//! with [`BridgeError::RtNotRunning`]; the thread keeps trying to open the services, so a
//! restarted core (or a restarted gateway) reconnects by itself. A core whose services have
//! another sample layout (built from another version) is [`BridgeError::IncompatibleLayout`].

mod ports;
mod worker;

#[cfg(test)]
mod tests;

pub use ports::{LayoutMismatch, OpenError};

use iceoryx2::prelude::*;
use mcm_shared::command::{DecodeError, Request};
use mcm_shared::reply::{Response, SafetyError};
use mcm_shared::sample::StateSample;
use mcm_shared::service::ServiceNames;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;
use tokio::sync::{broadcast, mpsc, oneshot, watch};

/// A request through the bridge failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BridgeError {
    #[error("the real-time core (mcm-rt, instance `{instance}`) is not running or not answering")]
    RtNotRunning { instance: String },
    #[error("cannot reach the real-time core (mcm-rt, instance `{instance}`): {error}")]
    IncompatibleLayout {
        instance: String,
        /// The open error, in words.
        error: String,
    },
    #[error("no reply from the real-time core within {seconds} s")]
    Timeout { seconds: f64 },
    #[error("publishing the command to the real-time core failed: {0}")]
    Publish(String),
    #[error(
        "the real-time core's answer cannot be read ({0}); mcm-rt and the gateway are from \
         different MCM versions: rebuild both from the same version"
    )]
    Undecodable(DecodeError),
    #[error("the gateway is shutting down")]
    ShuttingDown,
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
}

/// The async side of the bridge; cheap to clone.
#[derive(Clone)]
pub struct Bridge {
    jobs: mpsc::Sender<Job>,
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
        let (names_, errors, flight_dir, stop_) = (
            names.clone(),
            err_tx.clone(),
            flight_dir.to_string(),
            stop.clone(),
        );
        // The worker owns iceoryx2 ports, which are not `Send`: it is made on its thread.
        let handle = std::thread::Builder::new()
            .name("mcm-ipc-bridge".into())
            .spawn(move || {
                worker::Worker::new(names_, req_rx, state_tx, errors, flight_dir, stop_).run()
            })
            .expect("spawn the IPC bridge thread");
        let bridge = Bridge {
            jobs: req_tx,
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

    /// Send the requests of one command for the connection `client_id` (in order; several for
    /// a `pvt_points` batch) and wait for the answer to the last one.
    pub async fn request(
        &self,
        client_id: u64,
        requests: Vec<Request>,
        timeout: Duration,
    ) -> Result<Answer, BridgeError> {
        let (tx, rx) = oneshot::channel();
        self.jobs
            .send(Job {
                client_id,
                requests,
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
