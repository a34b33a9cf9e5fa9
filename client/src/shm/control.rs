//! The control loop, in the manner of libfranka: a callback gets each cycle's state and returns
//! what the arm should do next; the loop sends it at once, so that it reaches the core before
//! the next cycle starts and is applied in that cycle.
//!
//! ```no_run
//! use mcm_client::shm::{ControlOutput, ShmClient};
//! use mcm_shared::command::TorqueControl;
//! let mut mcm = ShmClient::connect("default")?;
//! mcm.torque_control(TorqueControl { timeout_s: Some(0.1), gravity_compensation: true })?;
//! let mut n = 0;
//! let summary = mcm.control(|_state| {
//!     n += 1;
//!     if n == 1000 { ControlOutput::Finish } else { ControlOutput::Torques([0.0; 6]) }
//! })?;
//! println!("{summary}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The loop ends cleanly: on `Finish` (the mode is left as it is: send `hold` or let the
//! torque or velocity timeout bring the arm to HOLD), and with a [`ControlError`] when the mode leaves the
//! one the loop started in (timeout, `hold` from anyone), a safety check trips, another client
//! takes control, a command is refused or cannot be sent, or no state comes. Every end carries the
//! [`ControlSummary`]: cycles run, cycles missed (states the callback never saw), and how many
//! answers to state `k` were applied in cycle `k + 1`.

use super::{SendError, ShmClient, ShmEvent, WaitError};
use mcm_shared::command::{DecodeError, PvtChunk, PvtPoint, Request, SetTorques, SetVelocities};
use mcm_shared::mode::Mode;
use mcm_shared::reply::{Outcome, Response, SafetyError};
use mcm_shared::sample::{Reply, StateSample};
use std::fmt;
use std::time::Duration;

/// What the callback asks for after a state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ControlOutput {
    /// `set_torques` (TORQUE_CONTROL).
    Torques([f64; mcm_shared::NUM_AXES]),
    /// One more point of the PVT stream (PVT mode; `pvt`'s `dt` should be the cycle period,
    /// and the stream should be a few points ahead, queued with `pvt_points` first).
    Pvt(PvtPoint),
    /// `set_velocities` [deg/s] (VELOCITY_CONTROL).
    Velocities([f64; mcm_shared::NUM_AXES]),
    /// End the loop.
    Finish,
}

/// Why a control loop ended without `Finish`.
#[derive(Debug, Clone, PartialEq)]
pub enum ControlEnd {
    /// The mode is no longer the one the loop ran in (timeout fallback, `hold`, a stop).
    ModeLeft { from: Mode, to: Mode },
    /// A safety check tripped.
    SafetyTrip(SafetyError),
    /// Another client controls the arm now (0: nobody).
    OwnershipLost { owner: u64 },
    /// The core refused one of the loop's commands.
    Refused(Response),
    /// The loop can only run in TORQUE_CONTROL, VELOCITY_CONTROL or PVT.
    NotControlling(Mode),
    /// A command could not be published.
    Send(SendError),
    /// No state came in time, or the listener of the state event failed.
    Wait(WaitError),
    /// The core's safety error record does not decode (a core of another MCM version).
    UnreadableSafetyError(DecodeError),
}

impl fmt::Display for ControlEnd {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ControlEnd::ModeLeft { from, to } => write!(f, "the mode changed from {from} to {to}"),
            ControlEnd::SafetyTrip(e) => write!(f, "{e}"),
            ControlEnd::OwnershipLost { owner: 0 } => {
                f.write_str("this client no longer controls the arm (nobody does)")
            }
            ControlEnd::OwnershipLost { owner } => {
                write!(f, "another client (id {owner:#x}) controls the arm now")
            }
            ControlEnd::Refused(r) => write!(f, "{}", r.outcome.words(r.kind)),
            ControlEnd::NotControlling(m) => write!(
                f,
                "the control loop runs in TORQUE_CONTROL, VELOCITY_CONTROL or PVT, the mode is {m}; enter one first"
            ),
            ControlEnd::Send(e) => write!(f, "{e}"),
            ControlEnd::Wait(e) => write!(f, "{e}"),
            ControlEnd::UnreadableSafetyError(e) => write!(
                f,
                "the core's safety error record does not read ({e}); build the client from the same MCM version as the core"
            ),
        }
    }
}

/// A control loop that ended without `Finish`: why, and what it did until then.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the control loop ended after {} cycles: {end} ({summary})", summary.cycles)]
pub struct ControlError {
    pub end: Box<ControlEnd>,
    pub summary: ControlSummary,
}

/// What a control loop did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ControlSummary {
    /// States the callback was called with.
    pub cycles: u64,
    /// Cycles in between whose state the callback never saw (the loop was late).
    pub missed: u64,
    /// Commands sent.
    pub sent: u64,
    /// Answers to state `k` the core applied in cycle `k + 1` (on time), and later.
    pub on_time: u64,
    pub late: u64,
    /// Commands whose reply was not read before the loop ended.
    pub unanswered: u64,
}

impl ControlSummary {
    /// Share of the answered commands applied in the next cycle [%].
    pub fn on_time_percent(&self) -> f64 {
        let answered = self.on_time + self.late;
        if answered == 0 {
            0.0
        } else {
            100.0 * self.on_time as f64 / answered as f64
        }
    }
}

impl fmt::Display for ControlSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} cycles, {} missed, {} commands sent, applied in the next cycle {}/{} ({:.2} %), {} unanswered",
            self.cycles,
            self.missed,
            self.sent,
            self.on_time,
            self.on_time + self.late,
            self.on_time_percent(),
            self.unanswered
        )
    }
}

/// Slots of the ring that remembers, per request id, the cycle it answered.
const RING: usize = 256;

/// The replies to commands no call waits for: which cycle applied them, and the refusals.
#[derive(Debug)]
pub(crate) struct Tracker {
    /// `(request id, state seq k it answered)`, by request id modulo [`RING`].
    ring: [(u64, u64); RING],
    pub(crate) on_time: u64,
    pub(crate) late: u64,
    pub(crate) answered: u64,
}

impl Default for Tracker {
    fn default() -> Self {
        Tracker {
            ring: [(0, 0); RING],
            on_time: 0,
            late: 0,
            answered: 0,
        }
    }
}

impl Tracker {
    /// A command `id` was sent in answer to state `k` (0: to no state).
    pub(crate) fn sent(&mut self, id: u64, k: u64) {
        self.ring[(id % RING as u64) as usize] = (id, k);
    }

    /// A reply to a command no call waits for: counted; the response if it was not done.
    pub(crate) fn answered(&mut self, r: &Reply) -> Option<Response> {
        let slot = &mut self.ring[(r.request_id % RING as u64) as usize];
        if slot.0 == r.request_id && slot.1 != 0 {
            self.answered += 1;
            if r.cycle == slot.1 + 1 {
                self.on_time += 1;
            } else {
                self.late += 1;
            }
            *slot = (0, 0);
        }
        match Response::decode(r) {
            Ok(resp) if matches!(resp.outcome, Outcome::Done(_)) => None,
            Ok(resp) => Some(resp),
            // Not ours to judge here: an undecodable reply to a fire-and-forget command.
            Err(_) => None,
        }
    }

    fn reset(&mut self) {
        *self = Tracker::default();
    }
}

impl ShmClient {
    /// Run `callback` on every cycle's state until it returns `Finish` or the loop must end.
    /// The arm must be in TORQUE_CONTROL (the callback returns `Torques`), VELOCITY_CONTROL
    /// (`Velocities`) or PVT (`Pvt`), with this client controlling it. See the module docs.
    pub fn control<F>(&mut self, mut callback: F) -> Result<ControlSummary, ControlError>
    where
        F: FnMut(&StateSample) -> ControlOutput,
    {
        self.tracker.reset();
        let mut sum = ControlSummary::default();
        let end = |end: ControlEnd, sum: ControlSummary| ControlError {
            end: Box::new(end),
            summary: sum,
        };
        let mut s = self
            .wait_state()
            .map_err(|e| end(ControlEnd::Wait(e), sum))?;
        let mode = Mode::try_from(s.mode).unwrap_or(Mode::Error);
        if !matches!(
            mode,
            Mode::TorqueControl | Mode::VelocityControl | Mode::Pvt
        ) {
            return Err(end(ControlEnd::NotControlling(mode), sum));
        }
        let period = Duration::from_nanos(s.timing.period_ns.max(1_000_000));
        let state_wait = (period * 20).max(Duration::from_millis(100));
        let missed_at_start = self.missed;
        let result = loop {
            // Events of the previous cycles end the loop first.
            if let Some(why) = self.loop_event() {
                break Err(why);
            }
            let now = Mode::try_from(s.mode).unwrap_or(Mode::Error);
            if now != mode {
                break Err(ControlEnd::ModeLeft {
                    from: mode,
                    to: now,
                });
            }
            if s.owner_client_id != self.client_id {
                break Err(ControlEnd::OwnershipLost {
                    owner: s.owner_client_id,
                });
            }
            sum.cycles += 1;
            let req = match callback(&s) {
                ControlOutput::Finish => break Ok(()),
                ControlOutput::Torques(torques_nm) => {
                    Request::SetTorques(SetTorques { torques_nm })
                }
                ControlOutput::Velocities(velocities_deg_s) => {
                    Request::SetVelocities(SetVelocities { velocities_deg_s })
                }
                ControlOutput::Pvt(p) => Request::PvtPoints(
                    PvtChunk::new(&[p], true).expect("one point is a valid chunk"),
                ),
            };
            match self.send(&req) {
                Ok(id) => {
                    self.tracker.sent(id, s.seq);
                    sum.sent += 1;
                }
                Err(e) => break Err(ControlEnd::Send(e)),
            }
            s = match self.wait_state_timeout(state_wait) {
                Ok(s) => s,
                Err(e) => break Err(ControlEnd::Wait(e)),
            };
        };
        // The replies to the last commands come with the next cycle or two.
        for _ in 0..3 {
            if self.tracker.answered >= sum.sent || self.wait_state_timeout(state_wait).is_err() {
                break;
            }
        }
        sum.missed = self.missed - missed_at_start;
        sum.on_time = self.tracker.on_time;
        sum.late = self.tracker.late;
        sum.unanswered = sum.sent.saturating_sub(self.tracker.answered);
        match result {
            Ok(()) => Ok(sum),
            Err(e) => Err(end(e, sum)),
        }
    }

    /// The first event that ends a control loop (refusals and safety trips), if any.
    fn loop_event(&mut self) -> Option<ControlEnd> {
        if let Some(e) = self.next_event() {
            match e {
                ShmEvent::SafetyError(e) => return Some(ControlEnd::SafetyTrip(e)),
                ShmEvent::Refused(r) => return Some(ControlEnd::Refused(r)),
                ShmEvent::UnreadableSafetyError(e) => {
                    return Some(ControlEnd::UnreadableSafetyError(e));
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests;
