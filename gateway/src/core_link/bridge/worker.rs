//! The bridge thread: it blocks until woken (the core's state event, the doorbell of a job, or
//! a bounded timeout), then runs named steps: open the core's services (retrying), read the
//! state, route the replies in it to the requests waiting for them, report new safety errors,
//! publish queued samples as the scheduler allows, and give up on requests whose reply is
//! overdue.

use super::doorbell::Doorbell;
use super::event::{OPEN_RETRY, StateEvent};
use super::scheduler::Scheduler;
use super::wait::wait_readable;
use super::{Answer, BridgeError, Job, NoReply, SafetyEvent, Wake};
use mcm_client::shm::OpenError;
use mcm_client::shm::ports::{CorePorts, Peer};
use mcm_shared::command::DecodeError;
use mcm_shared::mode::CommandKind;
use mcm_shared::reply::{Response, SafetyError};
use mcm_shared::sample::{StateSample, flight_recorder_file};
use mcm_shared::service::ServiceNames;
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::sync::mpsc::{Receiver, TryRecvError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use tokio::sync::{broadcast, oneshot, watch};

/// State older than this means the real-time core stopped.
const STALE_AFTER: Duration = Duration::from_millis(500);
/// How often the state is read while the core's state event cannot be used.
pub(super) const FALLBACK_POLL: Duration = Duration::from_millis(1);
/// Longest wait for a wake-up while the event works (staleness and deadlines are checked at
/// least this often).
const IDLE_WAIT: Duration = Duration::from_millis(50);
/// The state opened this long without the event service: fall back to polling, and say so.
const EVENT_GRACE: Duration = Duration::from_secs(1);
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

/// A published sample not answered yet.
struct Unacked {
    client_id: u64,
    urgent: bool,
    sent: Instant,
}

/// A job in the scheduler, with the index of its next request to publish.
struct Queued {
    job: Job,
    next: usize,
}

/// What the bridge thread shares with the async side.
pub(super) struct Shared {
    pub(super) names: ServiceNames,
    pub(super) state_tx: watch::Sender<Option<Box<StateSample>>>,
    pub(super) errors: broadcast::Sender<SafetyEvent>,
    /// Every new state, in order (the ZeroMQ publication must not skip one; the watch above
    /// keeps only the newest). Sending with no receiver costs nothing but the state's copy.
    pub(super) every_state: broadcast::Sender<Arc<StateSample>>,
    pub(super) flight_dir: String,
    /// Rung by the async side after each message on the channel.
    pub(super) bell: Arc<Doorbell>,
    pub(super) open_error: Arc<Mutex<Option<BridgeError>>>,
}

pub(super) struct Worker {
    sh: Shared,
    ports: Option<CorePorts>,
    event: StateEvent,
    /// A failed wait was logged (once).
    logged_wait: bool,
    last_open_try: Option<Instant>,
    /// When the services were opened.
    opened_at: Instant,
    /// Why the services could not be opened, when that is worth telling requests (an
    /// incompatible layout); `None`: the core is simply not running.
    open_error: Option<BridgeError>,
    /// The last open error logged (each is logged once, not on every retry).
    logged: Option<String>,
    /// The fall-back to polling was logged (once until the event works again).
    logged_fallback: bool,
    /// The core publishes state.
    alive: bool,
    last_seq: u64,
    last_change: Instant,
    /// The newest safety error already reported.
    last_error_seq: Option<u64>,
    next_request: u64,
    sched: Scheduler<Queued>,
    /// Every sample published and not answered yet, by request id.
    unacked: HashMap<u64, Unacked>,
    /// Jobs fully published, by the request id of their last sample.
    pending: HashMap<u64, Pending>,
}

impl Worker {
    pub(super) fn new(sh: Shared) -> Worker {
        Worker {
            event: StateEvent::new(sh.names.clone()),
            logged_wait: false,
            sh,
            ports: None,
            last_open_try: None,
            opened_at: Instant::now(),
            open_error: None,
            logged: None,
            logged_fallback: false,
            alive: false,
            last_seq: 0,
            last_change: Instant::now(),
            last_error_seq: None,
            next_request: 1,
            sched: Scheduler::default(),
            unacked: HashMap::new(),
            pending: HashMap::new(),
        }
    }

    pub(super) fn run(mut self, wake: Receiver<Wake>) {
        crate::core_link::latency::on_thread_start();
        'run: loop {
            self.wait();
            // Cleared before the channel is drained: a job queued after the drain rings again.
            self.sh.bell.clear();
            loop {
                match wake.try_recv() {
                    Ok(Wake::Job(job)) => {
                        let urgent = job.urgent();
                        self.sched
                            .push(job.client_id, Queued { job, next: 0 }, urgent);
                    }
                    Ok(Wake::Stop) | Err(TryRecvError::Disconnected) => break 'run,
                    Err(TryRecvError::Empty) => break,
                }
            }
            self.open();
            if let Some(state) = self.read_state() {
                // The newest state first: a client that got a reply (or a safety error) and
                // asks for `status` at once must see the state that answered, not an older one.
                self.sh.state_tx.send_replace(Some(Box::new(state)));
                if self.sh.every_state.receiver_count() > 0 {
                    let _ = self.sh.every_state.send(Arc::new(state));
                }
                self.route_replies(&state);
                self.report_errors(&state);
            }
            self.publish();
            self.expire();
            self.note_fallback();
        }
        for (_, p) in self.pending.drain() {
            let _ = p.answer.send(Err(BridgeError::ShuttingDown));
        }
        for q in self.sched.drain() {
            let _ = q.job.answer.send(Err(BridgeError::ShuttingDown));
        }
    }

    /// Sleep until the doorbell rings, the core's state event fires or [`Worker::wait_time`]
    /// has passed; then take the event's notifications.
    fn wait(&mut self) {
        self.event.maintain();
        let bell = self.sh.bell.fd();
        let event = self.event.fd();
        let fds = [bell, event.unwrap_or(bell)];
        let n = 1 + usize::from(event.is_some());
        match wait_readable(&fds[..n], self.wait_time()) {
            Ok(ready) if ready.ready[1] => {
                self.event.drain();
            }
            Ok(_) => {}
            Err(e) => {
                if !self.logged_wait {
                    eprintln!(
                        "mcm-gateway: the bridge cannot wait for the state event and jobs \
                         ({e}); it checks every {} ms instead",
                        FALLBACK_POLL.as_millis()
                    );
                    self.logged_wait = true;
                }
                // Not a synchronisation: the pace of the fall-back when poll(2) itself fails.
                std::thread::sleep(FALLBACK_POLL);
                self.event.drain();
            }
        }
    }

    /// How long to block for the next wake-up: a bounded poll while the state event cannot be
    /// used, else until the next deadline (at most [`IDLE_WAIT`]).
    fn wait_time(&self) -> Duration {
        if self.ports.is_none() {
            let since = self.last_open_try.map_or(OPEN_RETRY, |t| t.elapsed());
            return OPEN_RETRY.saturating_sub(since);
        }
        if !self.alive {
            // The state is checked for a (re)started core; the event wakes the bridge sooner.
            return OPEN_RETRY;
        }
        if !self.event.live() {
            return FALLBACK_POLL;
        }
        let now = Instant::now();
        self.pending
            .values()
            .map(|p| p.deadline.saturating_duration_since(now))
            .fold(IDLE_WAIT, Duration::min)
    }

    /// Say once that the state event is not used, and once that it is used again.
    fn note_fallback(&mut self) {
        let live = self.event.live();
        if live && self.logged_fallback {
            eprintln!(
                "mcm-gateway: the state event `{}` of mcm-rt works again; the bridge wakes on \
                 each new state",
                self.sh.names.state_event()
            );
            self.logged_fallback = false;
        } else if !live
            && !self.logged_fallback
            && self.alive
            && self.opened_at.elapsed() > EVENT_GRACE
        {
            eprintln!(
                "mcm-gateway: cannot use the state event `{}` of mcm-rt (instance `{}`): the \
                 bridge reads the state every {} ms instead of waking on each new state",
                self.sh.names.state_event(),
                self.sh.names.instance(),
                FALLBACK_POLL.as_millis()
            );
            self.logged_fallback = true;
        }
    }

    /// What a request gets while the core cannot be reached.
    fn unavailable(&self) -> BridgeError {
        self.open_error
            .clone()
            .unwrap_or_else(|| BridgeError::RtNotRunning {
                instance: self.sh.names.instance().to_string(),
            })
    }

    fn set_open_error(&mut self, e: Option<BridgeError>) {
        if let Ok(mut shared) = self.sh.open_error.lock() {
            shared.clone_from(&e);
        }
        self.open_error = e;
    }

    /// Open the core's services, unless open or tried less than [`OPEN_RETRY`] ago (the same
    /// pace as the state event's own retries).
    fn open(&mut self) {
        if self.ports.is_some() || self.last_open_try.is_some_and(|t| t.elapsed() < OPEN_RETRY) {
            return;
        }
        self.last_open_try = Some(Instant::now());
        match CorePorts::open(&self.sh.names, Peer::Gateway) {
            Ok(p) => {
                self.ports = Some(p);
                self.opened_at = Instant::now();
                self.set_open_error(None);
                self.logged = None;
            }
            Err(e) if e.is_not_running() => self.set_open_error(None),
            Err(e) => self.open_failed(e),
        }
    }

    fn open_failed(&mut self, e: OpenError) {
        let text = e.to_string();
        if self.logged.as_ref() != Some(&text) {
            eprintln!(
                "mcm-gateway: cannot open the services of mcm-rt (instance `{}`): {text}",
                self.sh.names.instance()
            );
            self.logged = Some(text.clone());
        }
        let error =
            matches!(e, OpenError::Incompatible { .. }).then(|| BridgeError::IncompatibleLayout {
                instance: self.sh.names.instance().to_string(),
                error: e,
            });
        self.set_open_error(error);
    }

    /// Every request published and not answered gets "outcome unknown"; nothing is in flight
    /// any more.
    fn give_up_in_flight(&mut self, why: NoReply) {
        self.unacked.clear();
        self.sched.forget_in_flight();
        for (_, p) in self.pending.drain() {
            let _ = p.answer.send(Err(BridgeError::OutcomeUnknown(why)));
        }
    }

    /// The state, when the core published a new one since the last read. A core that stopped
    /// publishing (or restarted) leaves every published request with an unknown outcome.
    fn read_state(&mut self) -> Option<StateSample> {
        let state = self.ports.as_ref()?.state();
        if state.seq != self.last_seq {
            let restarted = self.alive && state.seq < self.last_seq;
            if restarted {
                self.give_up_in_flight(NoReply::CoreRestarted);
            }
            if !self.alive || restarted {
                // (Re)started core: replies and errors from before are gone.
                if let Some(ports) = self.ports.as_mut() {
                    ports.replies().skip_to(state.reply_head);
                }
                self.last_error_seq = Some(state.last_error.seq);
            }
            self.last_seq = state.seq;
            self.last_change = Instant::now();
            self.alive = true;
            return Some(state);
        }
        if self.alive && self.last_change.elapsed() > STALE_AFTER {
            self.alive = false;
            self.sh.state_tx.send_replace(None);
            self.give_up_in_flight(NoReply::CoreStopped);
        }
        None
    }

    /// Hand each new reply in the reply blocks to the request waiting for it, decoded. A reply
    /// no longer in the blocks (overwritten) is skipped; its request gets "outcome unknown"
    /// when its deadline passes.
    fn route_replies(&mut self, state: &StateSample) {
        let Some(ports) = self.ports.as_mut() else {
            return;
        };
        let (unacked, sched, pending) = (&mut self.unacked, &mut self.sched, &mut self.pending);
        // A reply overwritten before it was read is skipped: the request waiting for it times
        // out with "outcome unknown".
        ports.replies().read_to(state.reply_head, |r| {
            // Request ids are this gateway's own numbers: a reply to another client of the core
            // (a co-located controller numbering its own requests) has another client id.
            if let Entry::Occupied(u) = unacked.entry(r.request_id)
                && u.get().client_id == r.client_id
            {
                let u = u.remove();
                sched.answered(u.client_id, u.urgent);
            }
            if let Entry::Occupied(p) = pending.entry(r.request_id)
                && p.get().client_id == r.client_id
            {
                let p = p.remove();
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
        });
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
        let _ = self.sh.errors.send(SafetyEvent {
            error,
            mode: state.mode,
            file: flight_recorder_file(&self.sh.flight_dir, self.sh.names.instance(), record),
        });
    }

    /// Publish queued samples, one at a time, as the scheduler grants them (a long
    /// `pvt_points` batch goes out over several wake-ups, paced by the core's answers).
    fn publish(&mut self) {
        if self.ports.is_none() || !self.alive {
            let e = self.unavailable();
            for q in self.sched.drain() {
                let _ = q.job.answer.send(Err(e.clone()));
            }
            return;
        }
        while let Some(g) = self.sched.next() {
            let Some(q) = self.sched.job(g) else {
                self.sched.finish(g);
                continue;
            };
            if q.job.answer.is_closed() && !q.job.fire_and_forget {
                // Its connection went away (or gave up) before all of it was sent: the rest
                // is not sent (a batch is only queued with its last sample, so nothing of it
                // is executed).
                self.sched.finish(g);
                continue;
            }
            let Some(request) = q.job.requests.get(q.next) else {
                let q = self.sched.finish(g).expect("granted job exists");
                let _ = q.job.answer.send(Err(BridgeError::NoRequest));
                continue;
            };
            let (client_id, request_id) = (q.job.client_id, self.next_request);
            let ports = self.ports.as_ref().expect("checked above");
            if let Err(e) = ports.publish(request, client_id, request_id) {
                let q = self.sched.finish(g).expect("granted job exists");
                let _ = q.job.answer.send(Err(BridgeError::Publish(e)));
                continue;
            }
            self.next_request += 1;
            q.next += 1;
            let last = q.next == q.job.requests.len();
            self.sched.sent(g);
            self.unacked.insert(
                request_id,
                Unacked {
                    client_id,
                    urgent: g.urgent,
                    sent: Instant::now(),
                },
            );
            if last {
                let q = self.sched.finish(g).expect("granted job exists");
                self.pending.insert(
                    request_id,
                    Pending {
                        client_id: q.job.client_id,
                        kind: request_kind(&q.job),
                        deadline: Instant::now() + q.job.timeout,
                        timeout: q.job.timeout,
                        answer: q.job.answer,
                    },
                );
            }
        }
    }

    /// Forget samples whose answer never came (a lost reply), and give up on requests whose
    /// reply is overdue: they were published, so their outcome is unknown.
    fn expire(&mut self) {
        let mut lost = Vec::new();
        self.unacked.retain(|_, u| {
            let keep = u.sent.elapsed() < UNACKED_EXPIRY;
            if !keep {
                lost.push((u.client_id, u.urgent));
            }
            keep
        });
        for (client, urgent) in lost {
            self.sched.answered(client, urgent);
        }
        let now = Instant::now();
        let expired: Vec<u64> = self
            .pending
            .iter()
            .filter(|(_, p)| now >= p.deadline)
            .map(|(id, _)| *id)
            .collect();
        for id in expired {
            if let Some(p) = self.pending.remove(&id) {
                let _ = p
                    .answer
                    .send(Err(BridgeError::OutcomeUnknown(NoReply::Timeout {
                        seconds: p.timeout.as_secs_f64(),
                    })));
            }
        }
    }
}

/// The kind of the request whose reply answers the job (its last one).
fn request_kind(job: &Job) -> CommandKind {
    job.requests
        .last()
        .map_or(CommandKind::Status, mcm_shared::command::Request::kind)
}
