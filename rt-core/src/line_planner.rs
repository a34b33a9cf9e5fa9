//! Where the lines of `move_linear` are planned: beside the cycle, never in it.
//!
//! Planning a line ([`LinePlan::plan`]) checks the whole path and takes milliseconds (about
//! 1.5 ms for 1 m), a third of the 5 ms period and far beyond the cycle's work budget; sampling
//! a plan takes under a microsecond. So the controller stays a deterministic function of its
//! inputs: on `move_linear` it posts a [`LineRequest`] (the start, the target) among its
//! outputs, the cycle ([`crate::cycle::Cycle`]) adds the kinematics with the active tool's TCP
//! ([`crate::cartesian::Cartesian`]) and hands the job to a [`LinePlanner`], and a later cycle
//! gives the controller the [`Planned`] line (or why not) among its inputs. The arm holds
//! where it is meanwhile.
//!
//! Two planners behind one interface:
//! - [`LinePlanner::inline`]: plans when the job is handed over, on the calling thread; the
//!   result is given in the next cycle. The deterministic tests, the simulation tester and the
//!   benchmarks use it (the same code path minus the thread), so their runs stay
//!   reproducible.
//! - [`LinePlanner::thread`]: the thread `mcm-rt-line` plans, at normal priority and away from
//!   the cycle's CPU (it is started before the cycle thread turns real-time, and inherits its
//!   placement: [`crate::realtime::setup_helper_thread`]). The hand-off is one slot allocated at
//!   set-up, owned in turn by the cycle and the planner through one atomic state: the cycle
//!   writes the job and wakes the planner (`Thread::unpark`: an atomic swap and at most one
//!   futex wake, no allocation, no lock, never blocking), the planner writes the result and
//!   gives the slot back, the cycle reads the result in a later cycle. A job handed over while
//!   the slot is busy waits in the cycle ([`LinePlanner::post`] says so).
//!
//! [`LinePlanner::post`], [`LinePlanner::finished`] and [`LinePlanner::release`] run inside the
//! cycle (no allocation, lock, blocking or logging; the inline planner's `post` plans, which is
//! allocation-free but long: only in virtual time). The planner thread does not.

use mcm_kinematics::{JointLimits, Kinematics, LineError, LinePlan, LineTarget};
use mcm_shared::NUM_AXES;
use std::cell::UnsafeCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::thread::{JoinHandle, Thread};

/// A line the controller wants planned: from `start` [rad] (the arm at rest there) to
/// `target`. `id` tells its result from that of an earlier request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineRequest {
    pub id: u64,
    pub start: [f64; NUM_AXES],
    pub target: LineTarget,
}

/// A request with the kinematics to plan it with (the active tool's TCP).
#[derive(Debug, Clone, Copy)]
pub struct LineJob {
    pub request: LineRequest,
    pub kin: Kinematics,
}

/// The answer to the request `id`: the checked plan, or why the line was refused.
#[derive(Debug, Clone)]
pub struct Planned {
    pub id: u64,
    pub result: Result<LinePlan, LineError>,
}

impl LineJob {
    /// Plan it within `limits`.
    fn plan(&self, limits: &JointLimits) -> Planned {
        let r = &self.request;
        Planned {
            id: r.id,
            result: LinePlan::plan(&self.kin, limits, &r.start, &r.target),
        }
    }
}

/// The axes' limits a line is planned within: the controller's own (`JointParams`), so that a
/// line is planned within the limits its joint moves are.
pub fn joint_limits(p: &crate::params::JointParams) -> JointLimits {
    JointLimits {
        velocity: p.limits.map(|l| l.velocity),
        acceleration: p.limits.map(|l| l.acceleration),
        jerk: p.limits.map(|l| l.jerk),
    }
}

/// The planner of the cycle's lines (see the module doc).
pub struct LinePlanner {
    how: How,
}

enum How {
    /// Planned when posted; the result waits here (on the heap: about 13 kB).
    Inline {
        limits: JointLimits,
        done: Box<Option<Planned>>,
    },
    Thread(ThreadPlanner),
}

impl LinePlanner {
    /// A planner that plans on the calling thread when a job is posted, within `limits`.
    pub fn inline(limits: JointLimits) -> LinePlanner {
        LinePlanner {
            how: How::Inline {
                limits,
                done: Box::new(None),
            },
        }
    }

    /// A planner on its own thread (`mcm-rt-line`, the calling thread's scheduling and CPUs),
    /// within `limits`.
    pub fn thread(limits: JointLimits) -> std::io::Result<LinePlanner> {
        Ok(LinePlanner {
            how: How::Thread(ThreadPlanner::start(limits)?),
        })
    }

    /// Hand a copy of `job` over; `false` while the planner is still busy with an earlier one
    /// (or its result was not released yet): post it again in a later cycle.
    pub fn post(&mut self, job: &LineJob) -> bool {
        match &mut self.how {
            How::Inline { limits, done } => {
                if done.is_some() {
                    return false;
                }
                **done = Some(job.plan(limits));
                true
            }
            How::Thread(t) => t.post(job),
        }
    }

    /// The result of the last job, once planned (until [`LinePlanner::release`]).
    pub fn finished(&self) -> Option<&Planned> {
        match &self.how {
            How::Inline { done, .. } => done.as_ref().as_ref(),
            How::Thread(t) => t.finished(),
        }
    }

    /// The result was taken: the planner may take the next job.
    pub fn release(&mut self) {
        match &mut self.how {
            How::Inline { done, .. } => **done = None,
            How::Thread(t) => t.release(),
        }
    }
}

/// The slot's owner: the cycle while [`IDLE`] or [`DONE`], the planner thread while
/// [`REQUESTED`].
const IDLE: u8 = 0;
const REQUESTED: u8 = 1;
const DONE: u8 = 2;

/// The hand-off slot, allocated at set-up.
struct Slot {
    state: AtomicU8,
    stop: AtomicBool,
    job: UnsafeCell<Option<LineJob>>,
    done: UnsafeCell<Option<Planned>>,
}

// SAFETY: `job` and `done` are only touched by the side that owns the slot by `state` (see
// `IDLE`): the cycle while IDLE or DONE, the planner while REQUESTED; each hand-over is a
// release store that the other side's acquire load sees before it touches them.
unsafe impl Sync for Slot {}

struct ThreadPlanner {
    slot: Arc<Slot>,
    thread: Thread,
    handle: Option<JoinHandle<()>>,
}

impl ThreadPlanner {
    fn start(limits: JointLimits) -> std::io::Result<ThreadPlanner> {
        let slot = Arc::new(Slot {
            state: AtomicU8::new(IDLE),
            stop: AtomicBool::new(false),
            job: UnsafeCell::new(None),
            done: UnsafeCell::new(None),
        });
        let theirs = Arc::clone(&slot);
        let handle = std::thread::Builder::new()
            .name("mcm-rt-line".into())
            // `LinePlan::plan` uses about 30 kB of stack; room for it and its result.
            .stack_size(1 << 20)
            .spawn(move || plan_loop(&theirs, &limits))?;
        Ok(ThreadPlanner {
            slot,
            thread: handle.thread().clone(),
            handle: Some(handle),
        })
    }

    fn post(&mut self, job: &LineJob) -> bool {
        if self.slot.state.load(Ordering::Acquire) != IDLE {
            return false;
        }
        // SAFETY: IDLE: the cycle owns the slot (see `Slot`).
        unsafe { *self.slot.job.get() = Some(*job) };
        self.slot.state.store(REQUESTED, Ordering::Release);
        self.thread.unpark();
        true
    }

    fn finished(&self) -> Option<&Planned> {
        if self.slot.state.load(Ordering::Acquire) != DONE {
            return None;
        }
        // SAFETY: DONE: the cycle owns the slot until `release` gives it back, and `release`
        // takes `&mut self`, so this borrow ends before.
        unsafe { (*self.slot.done.get()).as_ref() }
    }

    fn release(&mut self) {
        if self.slot.state.load(Ordering::Acquire) == DONE {
            self.slot.state.store(IDLE, Ordering::Release);
        }
    }
}

impl Drop for ThreadPlanner {
    fn drop(&mut self) {
        self.slot.stop.store(true, Ordering::Release);
        self.thread.unpark();
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

/// The planner thread: plan each job handed over, until told to stop.
fn plan_loop(slot: &Slot, limits: &JointLimits) {
    while !slot.stop.load(Ordering::Acquire) {
        if slot.state.load(Ordering::Acquire) != REQUESTED {
            // Woken by `post` or `drop` (an `unpark` before this `park` makes it return at
            // once, so no wake-up is lost); a spurious return only looks again.
            std::thread::park();
            continue;
        }
        // SAFETY: REQUESTED: this thread owns the slot until it stores DONE.
        let Some(job) = (unsafe { (*slot.job.get()).take() }) else {
            // Never handed over without a job; give the slot back rather than hold it.
            slot.state.store(IDLE, Ordering::Release);
            continue;
        };
        let planned = job.plan(limits);
        // SAFETY: as above.
        unsafe { *slot.done.get() = Some(planned) };
        slot.state.store(DONE, Ordering::Release);
    }
}

#[cfg(test)]
mod tests;
