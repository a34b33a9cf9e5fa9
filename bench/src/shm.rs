//! The torque loop over shared memory, as a co-located controller runs it: the core's services
//! opened through the client library's layer ([`CorePorts`]: the state blackboard and its reply
//! blocks, the command service, with the versions checked; [`Replies`]: the reply blocks read
//! in order, as the gateway's bridge and `mcm_client::shm::ShmClient` read them), and the state
//! event (`mcm/<i>/state-ready`) waited on; where mcm-rt offers no state event, the blackboard
//! is polled every [`POLL`] instead, and the result says so.
//!
//! [`Replies`]: mcm_client::shm::replies::Replies

use crate::error::BenchError;
use crate::loopmatch::{Answer, LEVELS_NM, Observation, classify, level_of, tally};
use crate::torque::{LoopOutcome, median};
use iceoryx2::port::listener::{Listener, ListenerWaitError};
use iceoryx2::prelude::ipc;
use mcm_client::shm::ports::{CorePorts, Peer};
use mcm_shared::command::{Request, SetTorques, TorqueControl};
use mcm_shared::mode::{CommandKind, Mode};
use mcm_shared::reply::{Outcome, Reason, Response};
use mcm_shared::sample::StateSample;
use mcm_shared::service::ServiceNames;
use std::time::{Duration, Instant};

/// Blackboard polling interval when there is no state event.
pub const POLL: Duration = Duration::from_micros(50);
/// Longest wait for a new state or for a reply.
const WAIT: Duration = Duration::from_secs(2);
const BASELINE_STATES: usize = 10;
const TAIL_STATES: usize = 3;

/// A shared-memory client of the core.
pub struct ShmClient {
    // Before `ports`: dropped before the node it was made through.
    listener: Option<Listener<ipc::Service>>,
    ports: CorePorts,
    client_id: u64,
    next_request: u64,
    /// `set_torques` replies to this client that were not `Done`, with the first one's words.
    pub refused: u64,
    pub first_refusal: Option<String>,
    /// Replies overwritten in the reply blocks before this client read them (any client's).
    pub overwritten: u64,
}

impl ShmClient {
    pub fn open(names: &ServiceNames) -> Result<ShmClient, BenchError> {
        let mut ports = CorePorts::open(names, Peer::Client)?;
        // Poll when the state event does not exist; any other failure to open it is an error.
        let listener = match ports.open_state_event() {
            Ok(l) => Some(l),
            Err(e) if e.is_not_running() => None,
            Err(e) => return Err(e.into()),
        };
        let head = ports.state().reply_head;
        ports.replies().skip_to(head);
        Ok(ShmClient {
            listener,
            ports,
            client_id: (u64::from(std::process::id()) << 32) | 0xBE_0000,
            next_request: 1,
            refused: 0,
            first_refusal: None,
            overwritten: 0,
        })
    }

    fn err(&self, what: String) -> BenchError {
        BenchError::Shm {
            instance: self.ports.names().instance().to_string(),
            what,
        }
    }

    pub fn wait_mode(&self) -> &'static str {
        if self.listener.is_some() {
            "state event"
        } else {
            "blackboard polled every 50 us (no state event)"
        }
    }

    pub fn latest(&self) -> StateSample {
        self.ports.state()
    }

    /// The first state newer than cycle `seq`.
    pub fn next_state(&self, seq: u64) -> Result<StateSample, BenchError> {
        let deadline = Instant::now() + WAIT;
        loop {
            let s = self.latest();
            if s.seq > seq {
                return Ok(s);
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(self.err(format!("no state after cycle {seq} within {WAIT:?}")));
            }
            match &self.listener {
                // A wait cut short by a signal (the process stopped and continued) ends like a
                // wake-up: the state is read again and the wait resumes with the time left.
                Some(l) => match l.timed_wait(|_| {}, left.min(Duration::from_millis(20))) {
                    Ok(_) | Err(ListenerWaitError::InterruptSignal) => {}
                    Err(e) => return Err(self.err(format!("wait for the state event: {e:?}"))),
                },
                None => std::thread::sleep(POLL),
            }
        }
    }

    /// Publish `req`; its request id.
    pub fn send(&mut self, req: &Request) -> Result<u64, BenchError> {
        let id = self.next_request;
        self.next_request += 1;
        self.ports.publish(req, self.client_id, id)?;
        Ok(id)
    }

    /// Read the replies published up to `s`; the response to `want`, if among them. Replies to
    /// this client that are not `Done` are counted in `refused`. Inside the measured loop:
    /// allocates nothing but the words of the first refusal.
    pub fn scan_replies(&mut self, s: &StateSample, want: Option<u64>) -> Option<Response> {
        let client = self.client_id;
        let (refused, first_refusal) = (&mut self.refused, &mut self.first_refusal);
        let mut found = None;
        let scan = self.ports.replies().read_to(s.reply_head, |r| {
            if r.client_id != client {
                return;
            }
            let Ok(resp) = Response::decode(r) else {
                return;
            };
            if resp.kind == CommandKind::SetTorques && !matches!(resp.outcome, Outcome::Done(_)) {
                *refused += 1;
                first_refusal.get_or_insert_with(|| resp.outcome.words(resp.kind).to_string());
            }
            if Some(r.request_id) == want {
                found = Some(resp);
            }
        });
        self.overwritten += scan.overwritten;
        found
    }

    /// Send `req` and wait for its response.
    pub fn call(&mut self, req: &Request) -> Result<Response, BenchError> {
        let id = self.send(req)?;
        let mut seq = self.latest().seq;
        let deadline = Instant::now() + WAIT;
        while Instant::now() < deadline {
            let s = self.next_state(seq)?;
            seq = s.seq;
            if let Some(r) = self.scan_replies(&s, Some(id)) {
                return Ok(r);
            }
        }
        Err(self.err(format!("no reply to {req:?} within {WAIT:?}")))
    }

    /// `call`, requiring `Done`.
    pub fn ok(&mut self, req: &Request) -> Result<(), BenchError> {
        let r = self.call(req)?;
        match r.outcome {
            Outcome::Done(_) => Ok(()),
            o => Err(self.err(format!("{req:?} was answered {o:?}"))),
        }
    }
}

fn set_torques(axis6_nm: f64) -> Request {
    Request::SetTorques(SetTorques {
        torques_nm: [0.0, 0.0, 0.0, 0.0, 0.0, axis6_nm],
    })
}

/// The loop over shared memory for `cycles` answers; `kt6`: axis 6's torque per ampere.
/// `note` receives what the run could not do (control ownership not available yet).
pub fn shm_loop(
    names: &ServiceNames,
    cycles: u64,
    kt6: f64,
    note: &mut Vec<String>,
) -> Result<LoopOutcome, BenchError> {
    let mut c = ShmClient::open(names)?;
    let mut out = LoopOutcome {
        wait_mode: c.wait_mode(),
        ..LoopOutcome::default()
    };
    c.ok(&Request::Hold)?;
    // The TCP loop's connection may still own motion for a moment after it closed.
    let deadline = Instant::now() + crate::torque::OWNER_WAIT;
    loop {
        match c.call(&Request::TakeControl)?.outcome {
            Outcome::Done(_) => break,
            Outcome::Refused(Reason::NotAvailable) => {
                note.push(
                    "shm loop: take_control is not available in this core (sent without it)".into(),
                );
                break;
            }
            Outcome::Refused(Reason::NotOwner { .. }) if Instant::now() < deadline => {
                std::thread::sleep(Duration::from_millis(50));
            }
            o => return Err(c.err(format!("take_control was answered {o:?}"))),
        }
    }
    c.ok(&Request::TorqueControl(TorqueControl {
        timeout_s: Some(crate::torque::SESSION_TIMEOUT_S),
        gravity_compensation: true,
    }))?;
    c.ok(&set_torques(0.0))?;
    let mut s = c.latest();
    let mut base = Vec::with_capacity(BASELINE_STATES);
    while base.len() < BASELINE_STATES {
        s = c.next_state(s.seq)?;
        c.send(&set_torques(0.0))?;
        base.push(s.current[5] * kt6);
    }
    out.baseline_nm = median(&mut base);
    // The first state after the zeros were in force.
    s = c.next_state(s.seq)?;
    let mut observations = Vec::with_capacity(cycles as usize + TAIL_STATES);
    let mut answers = Vec::with_capacity(cycles as usize);
    let mut k = 0u64;
    let mut tail = 0;
    while tail < TAIL_STATES {
        if s.mode != Mode::TorqueControl.to_wire() {
            out.ended_early = Some(format!(
                "left TORQUE_CONTROL after {k} answers (mode {})",
                s.mode
            ));
            break;
        }
        observations.push(Observation {
            cycle: s.seq,
            level: classify(s.current[5] * kt6 - out.baseline_nm),
        });
        if k < cycles {
            c.send(&set_torques(LEVELS_NM[level_of(k)]))?;
            answers.push(Answer {
                cycle: s.seq,
                level: level_of(k),
            });
            k += 1;
        } else {
            tail += 1;
        }
        c.scan_replies(&s, None);
        s = c.next_state(s.seq)?;
    }
    out.tally = tally(&observations, &answers);
    c.ok(&Request::Hold)?;
    // Give control back and say goodbye (refused as not available by a core without ownership).
    let _ = c.call(&Request::ReleaseControl);
    let _ = c.send(&Request::ClientGone);
    out.errors = c.refused;
    if let Some(r) = &c.first_refusal {
        note.push(format!("shm loop: first refused reply: {r}"));
    }
    if c.overwritten > 0 {
        note.push(format!(
            "shm loop: {} replies were overwritten in the reply blocks before they were read",
            c.overwritten
        ));
    }
    Ok(out)
}
