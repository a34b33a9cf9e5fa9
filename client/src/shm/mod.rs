//! The shared-memory client: the real-time core's own services, on the robot's computer.
//!
//! ```no_run
//! use mcm_client::shm::ShmClient;
//! let mut mcm = ShmClient::connect("default")?;
//! let s = mcm.wait_state()?; // the next cycle's state, woken by the core's event
//! println!("cycle {} mode {}", s.seq, s.mode);
//! mcm.hold()?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! - [`ShmClient::connect`] opens `mcm/<instance>/state` (blackboard), `mcm/<instance>/command`
//!   (publish-subscribe) and `mcm/<instance>/state-ready` (event), and checks that the running
//!   core's sample types are the ones this client was built with.
//! - Each client object has its own client id, `(pid << 32) | n`, stamped on every command
//!   with an increasing request id; the core's replies to it are found in the reply blocks by
//!   those two ids. The ownership rules bind it exactly as a TCP connection: the first motion
//!   command (or `take_control`) takes control, others are refused `not_owner`.
//! - Dropping the client sends `client_gone`: the core releases its control, and what it drove
//!   ends in HOLD. A process that dies without dropping it (killed) is released by the gateway
//!   within 200 ms (it checks that the owner's pid lives).
//! - The client is not `Send` (iceoryx2's ports are bound to their thread): create it on the
//!   thread that uses it.
//! - Each operation has its own error: [`OpenError`] (connect), [`SendError`] (a command sent
//!   without waiting), [`WaitError`] (the next state), [`RequestError`] (a command and its
//!   reply), [`WaitUntilError`] (a condition on the state). iceoryx2's errors are kept as
//!   their sources.
//!
//! The ports themselves ([`ports`]: opening the services with the version check, publishing)
//! and the reply lookup ([`replies`]) are the layer the gateway's bridge uses too.

mod client_id;
mod control;
mod error;
mod pending;
pub mod ports;
pub mod replies;
mod steps;

pub use client_id::client_process;
pub use control::{ControlEnd, ControlError, ControlOutput, ControlSummary};
pub use error::{RequestError, WaitError, WaitUntilError};
pub use ports::{LayoutMismatch, OpenError, SendError, describe};

use iceoryx2::port::listener::{Listener, ListenerWaitError};
use iceoryx2::prelude::ipc;
use mcm_shared::command::{
    Calibrate, CartesianFrame, IdentifyPayload, MoveAll, MoveAxis, MoveLinear, Pvt, PvtChunk,
    PvtPoint, Request, SetCartesianVelocity, SetTool, SetTorques, SetVelocities, SimCommand,
    TorqueControl, VelocityControl,
};
use mcm_shared::mode::CommandKind;
use mcm_shared::protocol::core_reply_within;
use mcm_shared::reply::{
    Done, InfoReply, MoveAllPlan, MoveLinearPlan, Outcome, PayloadReply, Response, SafetyError,
};
use mcm_shared::sample::StateSample;
use mcm_shared::service::{COMMAND_BUFFER, ServiceNames};
use mcm_shared::tool::Tool;
use ports::{CorePorts, Peer};
use std::collections::VecDeque;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

/// Default longest wait for the next state.
pub const STATE_TIMEOUT: Duration = Duration::from_millis(500);
/// Most commands of one client unanswered at a time (the core buffers 64 per publisher).
pub const MAX_IN_FLIGHT: usize = COMMAND_BUFFER / 4;
/// Spontaneous events kept for [`ShmClient::next_event`] (the oldest go first).
const EVENTS_KEPT: usize = 64;

/// The lower half of client ids: unique per client object in this process.
static NEXT_CLIENT: AtomicU32 = AtomicU32::new(1);

/// A command sent with [`ShmClient::submit`], whose reply [`ShmClient::take_reply`] returns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Submitted {
    id: u64,
    kind: CommandKind,
}

impl Submitted {
    /// The command's kind.
    pub fn kind(&self) -> CommandKind {
        self.kind
    }

    /// Its request id (unique per client).
    pub fn request_id(&self) -> u64 {
        self.id
    }
}

/// Something the core reported that answers no call of this client.
#[derive(Debug, Clone, PartialEq)]
pub enum ShmEvent {
    /// A safety check tripped (every client sees it once).
    SafetyError(SafetyError),
    /// The core's error record does not decode (a core of another version).
    UnreadableSafetyError(mcm_shared::command::DecodeError),
    /// A command sent without waiting (`set_torques`, `set_velocities`, a control loop's commands) was refused.
    Refused(Response),
}

/// A client of the MCM's shared-memory services. See the module docs.
pub struct ShmClient {
    // Before `ports`: dropped before the node it was made through.
    listener: Listener<ipc::Service>,
    ports: CorePorts,
    client_id: u64,
    next_request: u64,
    /// Newest state returned by `wait_state`.
    last_seq: u64,
    last_error_seq: u64,
    /// States (cycles) published but never returned by `wait_state`, since connect.
    missed: u64,
    /// Requests whose reply a call waits for, and their replies once read.
    pending: pending::Pending,
    events: VecDeque<ShmEvent>,
    /// The control loop's bookkeeping of replies to commands it did not wait for.
    pub(crate) tracker: control::Tracker,
}

impl ShmClient {
    /// Open the services of the MCM `instance` (`"default"` unless it was started with
    /// `--instance`).
    pub fn connect(instance: &str) -> Result<ShmClient, OpenError> {
        let names = ServiceNames::new(instance)?;
        let mut ports = CorePorts::open(&names, Peer::Client)?;
        let listener = ports.open_state_event()?;
        let s = ports.state();
        ports.replies().skip_to(s.reply_head);
        let n = NEXT_CLIENT.fetch_add(1, Ordering::Relaxed);
        Ok(ShmClient {
            listener,
            ports,
            client_id: (u64::from(std::process::id()) << 32) | u64::from(n),
            next_request: 1,
            last_seq: s.seq,
            last_error_seq: s.last_error.seq,
            missed: 0,
            pending: pending::Pending::default(),
            events: VecDeque::new(),
            tracker: control::Tracker::default(),
        })
    }

    /// This client's id, `(pid << 32) | n` (the core's `owner_client_id` when it controls the
    /// arm).
    pub fn client_id(&self) -> u64 {
        self.client_id
    }

    /// The instance this client is connected to.
    pub fn instance(&self) -> &str {
        self.ports.names().instance()
    }

    /// The newest state, without waiting (it may be the one `wait_state` returned last).
    pub fn latest(&self) -> StateSample {
        self.ports.state()
    }

    /// Cycles whose state `wait_state` never returned since connect (the caller was slower
    /// than the cycle).
    pub fn missed_states(&self) -> u64 {
        self.missed
    }

    /// The next cycle's state: the first state newer than the last one returned, waiting for
    /// the core's state event (no spinning) at most [`STATE_TIMEOUT`].
    pub fn wait_state(&mut self) -> Result<StateSample, WaitError> {
        self.wait_state_timeout(STATE_TIMEOUT)
    }

    /// [`ShmClient::wait_state`] with its own bound; [`WaitError::Timeout`] when no new state
    /// came within `timeout`.
    pub fn wait_state_timeout(&mut self, timeout: Duration) -> Result<StateSample, WaitError> {
        let deadline = Instant::now() + timeout;
        loop {
            let s = self.ports.state();
            if s.seq != self.last_seq {
                if s.seq > self.last_seq + 1 && self.last_seq != 0 {
                    self.missed += s.seq - self.last_seq - 1;
                }
                self.last_seq = s.seq;
                self.absorb(&s);
                return Ok(s);
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(WaitError::Timeout {
                    waited: timeout,
                    last_seq: self.last_seq,
                });
            }
            // Wakes on the core's notification after its next publish (or a pending one: the
            // loop then reads the state again and waits once more). A signal that interrupts
            // the wait (a stop and continue, a handled signal) is no error: the loop reads the
            // state and waits again for the time left.
            match self.listener.timed_wait(|_| {}, left) {
                Ok(_) | Err(ListenerWaitError::InterruptSignal) => {}
                Err(source) => {
                    return Err(WaitError::Listener {
                        service: self.ports.names().state_event(),
                        source,
                    });
                }
            }
        }
    }

    /// Read the replies and the safety error a new state announces.
    fn absorb(&mut self, s: &StateSample) {
        let client = self.client_id;
        let (pending, tracker) = (&mut self.pending, &mut self.tracker);
        let mut refused = Vec::new();
        let scan = self.ports.replies().read_to(s.reply_head, |r| {
            if r.client_id != client || pending.offer(r) {
                return;
            }
            if let Some(resp) = tracker.answered(r) {
                refused.push(resp);
            }
        });
        if scan.overwritten > 0 {
            self.pending.overwritten();
        }
        for r in refused {
            self.push_event(ShmEvent::Refused(r));
        }
        if s.last_error.seq != self.last_error_seq {
            self.last_error_seq = s.last_error.seq;
            match SafetyError::decode(&s.last_error) {
                Ok(Some(e)) => self.push_event(ShmEvent::SafetyError(e)),
                Ok(None) => {}
                Err(e) => self.push_event(ShmEvent::UnreadableSafetyError(e)),
            }
        }
    }

    fn push_event(&mut self, e: ShmEvent) {
        if self.events.len() == EVENTS_KEPT {
            self.events.pop_front();
        }
        self.events.push_back(e);
    }

    /// The oldest event not taken yet (events are collected while states are read).
    pub fn next_event(&mut self) -> Option<ShmEvent> {
        self.events.pop_front()
    }

    /// Publish `req` with this client's id and a new request id; the request id.
    pub fn send(&mut self, req: &Request) -> Result<u64, SendError> {
        let id = self.next_request;
        self.next_request += 1;
        self.ports.publish(req, self.client_id, id)?;
        Ok(id)
    }

    /// Send `req` without waiting; its reply is collected as states are read
    /// ([`ShmClient::wait_state`]) and taken with [`ShmClient::take_reply`]. For a program whose
    /// loop must not stop at a command: it reads a state every cycle and looks for the reply.
    /// A reply that never comes (the core stopped, replies overwritten) is the caller's to time
    /// out, within [`core_reply_within`] of the command; [`ShmClient::forget`] then stops
    /// keeping it. A `pvt_points` batch is one [`Request::PvtPoints`] chunk here.
    pub fn submit(&mut self, req: &Request) -> Result<Submitted, SendError> {
        let mut id = [0u64];
        let mut pending = std::mem::take(&mut self.pending);
        let sent = pending.send_each(std::slice::from_ref(req), &mut id, |r| self.send(r));
        self.pending = pending;
        sent?;
        Ok(Submitted {
            id: id[0],
            kind: req.kind(),
        })
    }

    /// The outcome of a [`ShmClient::submit`]ted command once its reply has been read; `None`
    /// while it has not. After `Some`, the request is no longer kept.
    pub fn take_reply(&mut self, s: &Submitted) -> Option<Result<Done, RequestError>> {
        self.pending.take(s.id).map(|r| outcome(s.kind, &r))
    }

    /// Stop keeping the reply of a [`ShmClient::submit`]ted command (one given up on).
    pub fn forget(&mut self, s: &Submitted) {
        self.pending.forget(&[s.id]);
    }

    /// Send `requests` (of `kind`, at most [`MAX_IN_FLIGHT`]) and wait for their replies, as
    /// long as the core may take ([`core_reply_within`]: 5 s, `calibrate` 600 s, as the gateway
    /// waits); the first that is not `Done` ends the wait with its error, else the last one's
    /// `Done`. However the call ends (a send that fails, a refusal, no reply in time), none of
    /// its requests is waited for afterwards.
    fn send_and_wait(
        &mut self,
        kind: CommandKind,
        requests: &[Request],
    ) -> Result<Done, RequestError> {
        let mut ids = [0u64; MAX_IN_FLIGHT];
        let ids = &mut ids[..requests.len()];
        let mut pending = std::mem::take(&mut self.pending);
        let sent = pending.send_each(requests, ids, |r| self.send(r));
        self.pending = pending;
        sent?;
        let result = self.wait_replies(kind, ids, core_reply_within(kind));
        let overwritten = self.pending.forget(ids);
        result.map_err(|e| match e {
            RequestError::OutcomeUnknown {
                command, waited, ..
            } => RequestError::OutcomeUnknown {
                command,
                waited,
                overwritten,
            },
            e => e,
        })
    }

    /// Wait for the replies to `ids` (sent by this client) at most `timeout`; the first that
    /// is not `Done` ends the wait with its error, else the last one's `Done`.
    fn wait_replies(
        &mut self,
        kind: CommandKind,
        ids: &[u64],
        timeout: Duration,
    ) -> Result<Done, RequestError> {
        let start = Instant::now();
        let deadline = start + timeout;
        let mut last = Done::Ack;
        for &id in ids {
            loop {
                if let Some(r) = self.pending.take(id) {
                    // A refused chunk ends the batch; the others' replies are dropped.
                    last = outcome(kind, &r)?;
                    break;
                }
                let left = deadline.saturating_duration_since(Instant::now());
                // No reply in time, or the core stopped publishing: the outcome is unknown.
                let gave_up = left.is_zero()
                    || match self.wait_state_timeout(left.min(STATE_TIMEOUT)) {
                        Ok(_) => false,
                        Err(WaitError::Timeout { .. }) => true,
                        Err(e) => return Err(e.into()),
                    };
                if gave_up {
                    return Err(RequestError::OutcomeUnknown {
                        command: kind,
                        waited: start.elapsed(),
                        // Set by `send_and_wait`, which knows.
                        overwritten: false,
                    });
                }
            }
        }
        Ok(last)
    }

    /// Send `req` and wait for its reply, as long as the core may take for it
    /// ([`core_reply_within`]: 5 s, `calibrate` 600 s, as the gateway waits).
    pub fn request(&mut self, req: &Request) -> Result<Done, RequestError> {
        self.send_and_wait(req.kind(), std::slice::from_ref(req))
    }

    fn ack(&mut self, req: Request) -> Result<(), RequestError> {
        self.request(&req).map(|_| ())
    }

    /// Enter HOLD (open to every client).
    pub fn hold(&mut self) -> Result<(), RequestError> {
        self.ack(Request::Hold)
    }

    /// The core's number of axes and cycle period.
    pub fn info(&mut self) -> Result<InfoReply, RequestError> {
        match self.request(&Request::Info)? {
            Done::Info(i) => Ok(i),
            other => Err(mismatch(CommandKind::Info, other)),
        }
    }

    /// Home the axes; returns when the calibration has finished.
    pub fn calibrate(&mut self, c: Calibrate) -> Result<(), RequestError> {
        self.ack(Request::Calibrate(c))
    }

    /// Enter RELEASE.
    pub fn release(&mut self) -> Result<(), RequestError> {
        self.ack(Request::Release)
    }

    /// Enter PVT with points spaced `dt_s`.
    pub fn pvt(&mut self, dt_s: f64) -> Result<(), RequestError> {
        self.ack(Request::Pvt(Pvt { dt_s }))
    }

    /// Enter TORQUE_CONTROL.
    pub fn torque_control(&mut self, t: TorqueControl) -> Result<(), RequestError> {
        self.ack(Request::TorqueControl(t))
    }

    /// Set the torques [Nm] without waiting: a refusal comes as [`ShmEvent::Refused`].
    pub fn set_torques(
        &mut self,
        torques_nm: [f64; mcm_shared::NUM_AXES],
    ) -> Result<(), SendError> {
        let id = self.send(&Request::SetTorques(SetTorques { torques_nm }))?;
        self.tracker.sent(id, 0);
        Ok(())
    }

    /// Enter VELOCITY_CONTROL (every axis starts at target velocity 0).
    pub fn velocity_control(&mut self, v: VelocityControl) -> Result<(), RequestError> {
        self.ack(Request::VelocityControl(v))
    }

    /// Set the joint velocities [deg/s] without waiting: a refusal comes as
    /// [`ShmEvent::Refused`].
    pub fn set_velocities(
        &mut self,
        velocities_deg_s: [f64; mcm_shared::NUM_AXES],
    ) -> Result<(), SendError> {
        let id = self.send(&Request::SetVelocities(SetVelocities { velocities_deg_s }))?;
        self.tracker.sent(id, 0);
        Ok(())
    }

    /// Set the TCP's velocity (linear [m/s], angular [deg/s], base or tool frame) without
    /// waiting: a refusal comes as [`ShmEvent::Refused`].
    pub fn set_cartesian_velocity(
        &mut self,
        linear_m_s: [f64; 3],
        angular_deg_s: [f64; 3],
        frame: CartesianFrame,
    ) -> Result<(), SendError> {
        let id = self.send(&Request::SetCartesianVelocity(SetCartesianVelocity {
            linear_m_s,
            angular_deg_s,
            frame,
        }))?;
        self.tracker.sent(id, 0);
        Ok(())
    }

    /// Set the tool the arm carries (its TCP and load), from the next cycle.
    pub fn set_tool(&mut self, tool: Tool) -> Result<(), RequestError> {
        self.ack(Request::SetTool(SetTool { tool }))
    }

    /// Estimate the load on the flange; answers once the arm is back where it started (under
    /// 30 s). With `apply` the estimate becomes the tool's mass and centre of mass.
    pub fn identify_payload(&mut self, apply: bool) -> Result<PayloadReply, RequestError> {
        match self.request(&Request::IdentifyPayload(IdentifyPayload { apply }))? {
            Done::Payload(p) => Ok(p),
            other => Err(mismatch(CommandKind::IdentifyPayload, other)),
        }
    }

    /// Move one axis (OK as the motion starts).
    pub fn move_axis(&mut self, m: MoveAxis) -> Result<(), RequestError> {
        self.ack(Request::MoveAxis(m))
    }

    /// Move all axes together; the plan.
    pub fn move_all(&mut self, m: MoveAll) -> Result<MoveAllPlan, RequestError> {
        match self.request(&Request::MoveAll(m))? {
            Done::MoveAll(p) => Ok(p),
            other => Err(mismatch(CommandKind::MoveAll, other)),
        }
    }

    /// Move the TCP on a straight line (`move_linear`); the line as planned (answered once the
    /// core's planner has checked the whole path, a few cycles after the request).
    pub fn move_linear(&mut self, m: MoveLinear) -> Result<MoveLinearPlan, RequestError> {
        match self.request(&Request::MoveLinear(m))? {
            Done::MoveLinear(p) => Ok(p),
            other => Err(mismatch(CommandKind::MoveLinear, other)),
        }
    }

    /// Queue a batch of PVT points (whole or not at all; at most
    /// [`MAX_POINTS_PER_BATCH`](mcm_shared::protocol::MAX_POINTS_PER_BATCH) points a batch, as
    /// over TCP).
    pub fn pvt_points(&mut self, points: &[PvtPoint]) -> Result<(), RequestError> {
        use mcm_shared::protocol::MAX_POINTS_PER_BATCH as MAX;
        if points.is_empty() || points.len() > MAX {
            return Err(RequestError::Argument {
                command: CommandKind::PvtPoints,
                problem: format!("{} points given; a batch has 1 to {MAX}", points.len()),
            });
        }
        let chunks: Vec<Request> = PvtChunk::batch(points).map(Request::PvtPoints).collect();
        for window in chunks.chunks(MAX_IN_FLIGHT) {
            self.send_and_wait(CommandKind::PvtPoints, window)?;
        }
        Ok(())
    }

    /// Take control of the arm's motion.
    pub fn take_control(&mut self) -> Result<(), RequestError> {
        self.ack(Request::TakeControl)
    }

    /// Give up control; what this client drove ends in HOLD.
    pub fn release_control(&mut self) -> Result<(), RequestError> {
        self.ack(Request::ReleaseControl)
    }

    /// Fault injection into the simulated robot (the ground truth is in the state's `sim_*`).
    pub fn sim(&mut self, c: SimCommand) -> Result<(), RequestError> {
        self.ack(Request::Sim(c))
    }
}

impl Drop for ShmClient {
    /// Tell the core this client is gone: it releases the client's control.
    fn drop(&mut self) {
        let _ = self.send(&Request::ClientGone);
    }
}

/// A reply's outcome as this client's result.
fn outcome(kind: CommandKind, r: &mcm_shared::sample::Reply) -> Result<Done, RequestError> {
    let resp = Response::decode(r).map_err(|error| RequestError::Undecodable {
        command: kind,
        error,
    })?;
    match resp.outcome {
        Outcome::Done(d) => Ok(d),
        Outcome::Refused(reason) => Err(RequestError::Refused {
            command: resp.kind,
            reason,
        }),
        Outcome::Failed(reason) => Err(RequestError::Failed {
            command: resp.kind,
            reason,
        }),
    }
}

fn mismatch(kind: CommandKind, got: Done) -> RequestError {
    RequestError::Undecodable {
        command: kind,
        error: mcm_shared::command::DecodeError::Mismatch {
            kind,
            problem: match got {
                Done::Ack => "a plain OK where figures were expected",
                Done::Info(_) => "an `info` answer",
                Done::MoveAll(_) => "a `move_all` answer",
                Done::Payload(_) => "an `identify_payload` answer",
                Done::MoveLinear(_) => "a `move_linear` answer",
            },
        },
    }
}
