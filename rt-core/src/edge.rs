//! The runner's edge: everything one cycle of the real-time loop does, in one call.
//!
//! [`Edge::cycle`] runs inside the cycle (no allocation, lock, blocking or logging): drain every
//! waiting command into the backlog and choose this cycle's ([`crate::intake`]: stops first, then
//! round robin over the clients), run the cycle with the simulator's edge when there is one and
//! compose the state with this cycle's timing ([`crate::runner::run_cycle`],
//! [`crate::publish::compose`]), keep the cycle in the flight recorder (and hand it over when a new
//! error appears), publish the state. [`Edge::end`] (also inside the cycle) does the deadline
//! arithmetic once the cycle's work is done. [`Edge::signal_state`] then wakes the state event's
//! listeners: still on the cycle thread, but outside the timed work (a failure is counted, never
//! logged). Only sleeping until the deadline and reading the clock stay in the loop around them
//! ([`crate::runner`]); the tests drive the same three calls back to back.
//!
//! ```no_run
//! # fn run<B: mcm_bus::Bus>(mut edge: mcm_rt_core::edge::Edge<B>) {
//! use mcm_rt_core::clock;
//! let mut next = edge.start(clock::now_ns());
//! loop {
//!     clock::sleep_until_ns(next);
//!     edge.cycle(clock::now_ns());
//!     next = edge.end(clock::now_ns());
//!     edge.signal_state();
//! }
//! # }
//! ```

use crate::clock;
use crate::controller::Controller;
use crate::cycle::Cycle;
use crate::flight::{FlightRecorder, Record};
use crate::intake::Intake;
use crate::ipc::{Drained, RtIpc};
use crate::publish::CycleClock;
use crate::runner::run_cycle;
use crate::sim_edge::SimEdge;
use crate::timing::Timing;
use mcm_bus::Bus;
use mcm_shared::sample::StateSample;

/// Span of one sub-histogram of the recent timing window (10 of them: about 10 s).
const TIMING_SLOT_NS: u64 = 1_000_000_000;
/// The timing percentiles are computed about this often.
const TIMING_REFRESH_NS: u64 = 100_000_000;

/// The cycle with its edges (IPC ports, simulator's edge, flight recorder) and the loop's
/// figures (wake-up latency, work time, overruns, failed receives).
pub struct Edge<B: Bus> {
    /// On the heap (about 230 kB): the edge moves cheaply and fits any thread's stack.
    cycle: Box<Cycle<B>>,
    sim: Option<SimEdge<B>>,
    ipc: RtIpc,
    recorder: FlightRecorder,
    intake: Intake,
    period_ns: u64,
    /// The thread got real-time scheduling.
    realtime: bool,
    /// Cycles run so far; the controller's time is `k * period`.
    k: u64,
    /// The deadline of the current (or next) cycle and when the current one woke up.
    next_ns: u64,
    wake_ns: u64,
    timing: Timing,
    overruns: u64,
    receive_errors: u64,
    notify_failures: u64,
    /// `seq` of the last error handed to the flight recorder.
    error_seq: u64,
}

/// What the loop did, once it stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Figures {
    pub cycles: u64,
    pub overruns: u64,
    pub latency_p99_ns: u64,
    pub latency_max_ns: u64,
    pub command_receive_errors: u64,
    /// Cycles whose state event could not be notified.
    pub notify_failures: u64,
    /// Cycles whose work took longer than the budget.
    pub over_budget: u64,
    /// The most commands that waited in the backlog at once.
    pub most_waiting: usize,
}

impl<B: Bus> Edge<B> {
    /// The edge of `cycle` at `period_ns` (whose work should take at most `work_budget_ns`),
    /// with the simulator's edge `sim` when the bus is the simulator; `realtime` says whether
    /// the thread got real-time scheduling.
    pub fn new(
        cycle: Box<Cycle<B>>,
        sim: Option<SimEdge<B>>,
        ipc: RtIpc,
        recorder: FlightRecorder,
        period_ns: u64,
        work_budget_ns: u64,
        realtime: bool,
    ) -> Self {
        Self {
            cycle,
            sim,
            ipc,
            recorder,
            intake: Intake::new(),
            period_ns,
            realtime,
            k: 0,
            next_ns: 0,
            wake_ns: 0,
            timing: Timing::new(
                period_ns,
                work_budget_ns,
                TIMING_SLOT_NS,
                TIMING_REFRESH_NS / period_ns.max(1),
            ),
            overruns: 0,
            receive_errors: 0,
            notify_failures: 0,
            error_seq: 0,
        }
    }

    /// Start the schedule at `now_ns`; the first deadline, one period later.
    pub fn start(&mut self, now_ns: u64) -> u64 {
        self.next_ns = now_ns + self.period_ns;
        self.next_ns
    }

    /// One cycle, woken at `wake_ns` for the current deadline: drain every waiting command
    /// into the backlog (a failed receive is counted; what came before it is kept) and choose
    /// this cycle's, run the cycle, stamp the timing figures, record the cycle (and hand the
    /// history over on a new error), publish the replies and the state.
    pub fn cycle(&mut self, wake_ns: u64) {
        self.wake_ns = wake_ns;
        self.timing.wake(wake_ns.saturating_sub(self.next_ns));
        let drained = self.ipc.drain(self.intake.free());
        received(drained, &mut self.intake, &mut self.receive_errors);
        let commands = self.intake.next_cycle();
        let clock = CycleClock {
            t_ns: wake_ns,
            unix_ns: clock::realtime_ns(),
            timing: self.timing.figures(self.overruns),
            not_realtime: !self.realtime,
            command_receive_errors: self.receive_errors,
        };
        run_cycle(
            &mut self.cycle,
            self.sim.as_mut(),
            self.k * self.period_ns,
            &clock,
            commands,
        );
        self.k += 1;
        let last_command = commands.last().map_or(0, |c| c.kind);
        let (view, s, _) = self.cycle.publish_parts();
        let first_reply = crate::publish::first_reply_seq(s, view);
        self.ipc
            .publish_replies(first_reply, s.seq, view.replies.replies());
        let s = self.cycle.state();
        let new_error = s.last_error.seq != self.error_seq;
        if new_error {
            self.error_seq = s.last_error.seq;
        }
        self.recorder.record(&Record::of(s, last_command));
        if new_error {
            self.recorder.trigger(&s.last_error);
        }
        self.ipc.publish(s);
    }

    /// The cycle's work ended at `end_ns`: note the work time; the next deadline. Missed
    /// deadlines are counted as overruns and the schedule starts again from `end_ns`.
    pub fn end(&mut self, end_ns: u64) -> u64 {
        self.timing.work(end_ns.saturating_sub(self.wake_ns));
        let (next, missed) = next_deadline(self.next_ns, end_ns, self.period_ns);
        self.next_ns = next;
        self.overruns += missed;
        self.next_ns
    }

    /// Wake the state event's listeners (after [`Edge::end`]: outside the timed work). A
    /// failure is counted in [`Figures::notify_failures`].
    pub fn signal_state(&mut self) {
        if self.ipc.notify_state().is_err() {
            self.notify_failures += 1;
        }
    }

    pub fn controller(&self) -> &Controller {
        self.cycle.controller()
    }

    /// The state sample of the last cycle, as published.
    pub fn state(&self) -> &StateSample {
        self.cycle.state()
    }

    /// The cycle (e.g. its bus, after the loop stopped).
    pub fn cycle_mut(&mut self) -> &mut Cycle<B> {
        &mut self.cycle
    }

    /// The loop's figures so far.
    pub fn figures(&self) -> Figures {
        let latency = self.timing.since_start();
        let timing = self.timing.figures(self.overruns);
        Figures {
            cycles: self.k,
            overruns: self.overruns,
            latency_p99_ns: latency.percentile(0.99),
            latency_max_ns: latency.max(),
            command_receive_errors: self.receive_errors,
            notify_failures: self.notify_failures,
            over_budget: timing.over_budget,
            most_waiting: self.intake.most_waiting(),
        }
    }
}

/// Take what a drain gave into the backlog; a failed drain counts in `errors` (the samples
/// received before the failure are kept, and the cycle goes on).
fn received(drained: Drained, intake: &mut Intake, errors: &mut u64) {
    intake.received(drained.count);
    if drained.error.is_some() {
        *errors += 1;
    }
}

/// The deadline after `next_ns` for a cycle whose work ended at `end_ns`, and how many
/// deadlines it missed: when it ended after that deadline, the schedule starts again from
/// `end_ns` (on the period's grid).
fn next_deadline(next_ns: u64, end_ns: u64, period_ns: u64) -> (u64, u64) {
    let next = next_ns + period_ns;
    if end_ns > next {
        let late = end_ns - next;
        (end_ns + period_ns - late % period_ns, late / period_ns + 1)
    } else {
        (next, 0)
    }
}

#[cfg(test)]
mod tests;
