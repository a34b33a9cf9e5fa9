//! The bridge thread: one loop over named steps, every millisecond. It opens the core's
//! services (retrying), reads the state, routes the replies in it to the requests waiting for
//! them, reports new safety errors, publishes waiting requests while the core's command buffer
//! has room, and times out what waited too long.

use super::ports::{OpenError, Ports, open_ports};
use super::{Answer, BridgeError, Job, SafetyEvent};
use mcm_shared::command::DecodeError;
use mcm_shared::mode::CommandKind;
use mcm_shared::reply::{Response, SafetyError};
use mcm_shared::sample::{
    REPLY_BLOCK, REPLY_BLOCKS, ReplyBlock, StateSample, flight_recorder_file, reply_location,
};
use mcm_shared::service::{COMMAND_BUFFER, ServiceNames};
use std::collections::{HashMap, VecDeque};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use tokio::sync::{broadcast, mpsc, oneshot, watch};

/// State older than this means the real-time core stopped.
const STALE_AFTER: Duration = Duration::from_millis(500);
/// Poll period of the blackboard.
const POLL: Duration = Duration::from_millis(1);
/// Time between two attempts to open the core's services.
const OPEN_RETRY: Duration = Duration::from_millis(100);
/// Samples published and not yet answered, at most (keeps the core's command buffer from
/// overflowing).
const MAX_IN_FLIGHT: usize = COMMAND_BUFFER / 2;
/// A published sample not answered within this time no longer counts as in flight.
const UNACKED_EXPIRY: Duration = Duration::from_secs(5);

/// A request whose last sample is published, waiting for its reply.
struct Pending {
    client_id: u64,
    kind: CommandKind,
    deadline: Instant,
    timeout: Duration,
    answer: oneshot::Sender<Result<Answer, BridgeError>>,
}

pub(super) struct Worker {
    names: ServiceNames,
    jobs: mpsc::Receiver<Job>,
    state_tx: watch::Sender<Option<Box<StateSample>>>,
    errors: broadcast::Sender<SafetyEvent>,
    flight_dir: String,
    stop: Arc<AtomicBool>,

    ports: Option<Ports>,
    last_open_try: Option<Instant>,
    /// Why the services could not be opened, when that is worth telling requests (an
    /// incompatible layout); `None`: the core is simply not running.
    open_error: Option<BridgeError>,
    /// The last open error logged (each is logged once, not on every retry).
    logged: Option<String>,
    /// The core publishes state.
    alive: bool,
    last_seq: u64,
    last_change: Instant,
    /// The newest reply already routed, and the newest safety error already reported.
    last_reply: u64,
    last_error_seq: Option<u64>,
    next_request: u64,
    /// Jobs waiting for room in the core's command buffer, with the index of their next
    /// request to publish.
    waiting: VecDeque<(Job, usize)>,
    /// Every sample published and not answered yet, with when it was published.
    unacked: HashMap<u64, Instant>,
    /// Jobs fully published, by the request id of their last sample.
    pending: HashMap<u64, Pending>,
}

impl Worker {
    pub(super) fn new(
        names: ServiceNames,
        jobs: mpsc::Receiver<Job>,
        state_tx: watch::Sender<Option<Box<StateSample>>>,
        errors: broadcast::Sender<SafetyEvent>,
        flight_dir: String,
        stop: Arc<AtomicBool>,
    ) -> Worker {
        Worker {
            names,
            jobs,
            state_tx,
            errors,
            flight_dir,
            stop,
            ports: None,
            last_open_try: None,
            open_error: None,
            logged: None,
            alive: false,
            last_seq: 0,
            last_change: Instant::now(),
            last_reply: 0,
            last_error_seq: None,
            next_request: 1,
            waiting: VecDeque::new(),
            unacked: HashMap::new(),
            pending: HashMap::new(),
        }
    }

    pub(super) fn run(mut self) {
        while !self.stop.load(Ordering::Relaxed) {
            self.open();
            if let Some(state) = self.read_state() {
                self.route_replies(&state);
                self.report_errors(&state);
                self.state_tx.send_replace(Some(Box::new(state)));
            }
            self.publish_waiting();
            self.expire();
            std::thread::sleep(POLL);
        }
        for (_, p) in self.pending.drain() {
            let _ = p.answer.send(Err(BridgeError::ShuttingDown));
        }
    }

    /// What a request gets while the core cannot be reached.
    fn unavailable(&self) -> BridgeError {
        self.open_error
            .clone()
            .unwrap_or_else(|| BridgeError::RtNotRunning {
                instance: self.names.instance().to_string(),
            })
    }

    /// Open the core's services, unless open or tried less than [`OPEN_RETRY`] ago.
    fn open(&mut self) {
        if self.ports.is_some() || self.last_open_try.is_some_and(|t| t.elapsed() < OPEN_RETRY) {
            return;
        }
        self.last_open_try = Some(Instant::now());
        match open_ports(&self.names) {
            Ok(p) => {
                self.ports = Some(p);
                self.open_error = None;
                self.logged = None;
            }
            Err(e) if e.is_not_running() => self.open_error = None,
            Err(e) => self.open_failed(&e),
        }
    }

    fn open_failed(&mut self, e: &OpenError) {
        let text = e.to_string();
        if self.logged.as_ref() != Some(&text) {
            eprintln!(
                "mcm-gateway: cannot open the services of mcm-rt (instance `{}`): {text}",
                self.names.instance()
            );
            self.logged = Some(text.clone());
        }
        self.open_error = matches!(e, OpenError::IncompatibleLayout { .. }).then(|| {
            BridgeError::IncompatibleLayout {
                instance: self.names.instance().to_string(),
                error: text,
            }
        });
    }

    /// The state, when the core published a new one since the last poll. A core that stopped
    /// publishing fails every pending request.
    fn read_state(&mut self) -> Option<StateSample> {
        let state = *self.ports.as_ref()?.state.get();
        if state.seq != self.last_seq {
            if !self.alive || state.seq < self.last_seq {
                // (Re)started core: replies and errors from before are gone.
                self.last_reply = state.reply_head;
                self.last_error_seq = Some(state.last_error.seq);
            }
            self.last_seq = state.seq;
            self.last_change = Instant::now();
            self.alive = true;
            return Some(state);
        }
        if self.alive && self.last_change.elapsed() > STALE_AFTER {
            self.alive = false;
            self.unacked.clear();
            self.state_tx.send_replace(None);
            let e = self.unavailable();
            for (_, p) in self.pending.drain() {
                let _ = p.answer.send(Err(e.clone()));
            }
        }
        None
    }

    /// Hand each new reply in the reply blocks to the request waiting for it, decoded.
    fn route_replies(&mut self, state: &StateSample) {
        let Some(ports) = self.ports.as_ref() else {
            return;
        };
        let oldest = state
            .reply_head
            .saturating_sub((REPLY_BLOCKS * REPLY_BLOCK) as u64 - 1)
            .max(1);
        let mut block: Option<(u32, ReplyBlock)> = None;
        for n in (self.last_reply + 1).max(oldest)..=state.reply_head {
            let (key, slot) = reply_location(n);
            if block.is_none_or(|(k, _)| k != key) {
                block = Some((key, *ports.reply_blocks[key as usize - 1].get()));
            }
            let Some((_, b)) = &block else { continue };
            let r = &b.replies[slot];
            if r.seq != n {
                // Overwritten (the gateway fell more than the blocks hold behind) or dropped by
                // the core; the request waiting for it times out with "outcome unknown".
                continue;
            }
            self.unacked.remove(&r.request_id);
            let ours = self
                .pending
                .get(&r.request_id)
                .is_some_and(|p| p.client_id == r.client_id);
            if ours && let Some(p) = self.pending.remove(&r.request_id) {
                let answer = match Response::decode(r) {
                    Ok(resp) if resp.kind == p.kind => Ok((resp, Box::new(*state))),
                    Ok(resp) => Err(BridgeError::Undecodable(DecodeError::Mismatch {
                        kind: resp.kind,
                        problem: "it answers a request of another kind",
                    })),
                    Err(e) => Err(BridgeError::Undecodable(e)),
                };
                let _ = p.answer.send(answer);
            }
        }
        self.last_reply = state.reply_head;
    }

    /// Broadcast a safety error not reported yet.
    fn report_errors(&mut self, state: &StateSample) {
        let record = &state.last_error;
        if self.last_error_seq == Some(record.seq) {
            return;
        }
        self.last_error_seq = Some(record.seq);
        let error = match SafetyError::decode(record) {
            Ok(None) => return,
            Ok(Some(e)) => Ok(e),
            Err(e) => Err(e),
        };
        let _ = self.errors.send(SafetyEvent {
            error,
            mode: state.mode,
            file: flight_recorder_file(&self.flight_dir, self.names.instance(), record),
        });
    }

    /// Take new jobs; publish their requests while the core's buffer has room (a long
    /// pvt_points batch goes out over several polls, paced by the core's answers).
    fn publish_waiting(&mut self) {
        while let Ok(job) = self.jobs.try_recv() {
            self.waiting.push_back((job, 0));
        }
        while let Some((job, next)) = self.waiting.front_mut() {
            let Some(p) = self.ports.as_ref().filter(|_| self.alive) else {
                let (job, _) = self.waiting.pop_front().expect("front exists");
                let _ = job.answer.send(Err(self.unavailable()));
                continue;
            };
            let mut failed = None;
            while *next < job.requests.len() && self.unacked.len() < MAX_IN_FLIGHT {
                let mut s = job.requests[*next].encode();
                s.client_id = job.client_id;
                s.request_id = self.next_request;
                self.next_request += 1;
                if let Err(e) = p.publisher.send_copy(s) {
                    failed = Some(BridgeError::Publish(format!("{e:?}")));
                    break;
                }
                self.unacked.insert(s.request_id, Instant::now());
                *next += 1;
            }
            if failed.is_none() && *next < job.requests.len() {
                break;
            }
            let (job, _) = self.waiting.pop_front().expect("front exists");
            match (failed, job.requests.last()) {
                (None, Some(last)) => {
                    self.pending.insert(
                        self.next_request - 1,
                        Pending {
                            client_id: job.client_id,
                            kind: last.kind(),
                            deadline: Instant::now() + job.timeout,
                            timeout: job.timeout,
                            answer: job.answer,
                        },
                    );
                }
                (Some(e), _) => {
                    let _ = job.answer.send(Err(e));
                }
                (None, None) => {
                    let _ = job.answer.send(Err(BridgeError::Publish(
                        "the command carries no request for the real-time core".into(),
                    )));
                }
            }
        }
    }

    /// Forget samples whose answer never came (a lost reply), and time out what waited too
    /// long.
    fn expire(&mut self) {
        self.unacked.retain(|_, t| t.elapsed() < UNACKED_EXPIRY);
        let now = Instant::now();
        let expired: Vec<u64> = self
            .pending
            .iter()
            .filter(|(_, p)| now >= p.deadline)
            .map(|(id, _)| *id)
            .collect();
        for id in expired {
            if let Some(p) = self.pending.remove(&id) {
                let _ = p.answer.send(Err(BridgeError::Timeout {
                    seconds: p.timeout.as_secs_f64(),
                }));
            }
        }
    }
}
