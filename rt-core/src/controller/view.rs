//! What the controller says about one cycle, in SI units: the view [`crate::publish`] composes
//! the published state sample from, and the outbox of the cycle's replies.
//!
//! Runs inside the cycle: fixed-capacity storage, no allocation.

use mcm_shared::NUM_AXES;
use mcm_shared::mode::Mode;
use mcm_shared::reply::SafetyError;
use mcm_shared::sample::{BusCounters, REPLIES_PER_CYCLE, Reply};

/// The replies of one cycle, in the order they were given (wire form, `seq` 0: the edge numbers
/// them when it publishes them). Holds [`REPLIES_PER_CYCLE`]; were more given in one cycle, the
/// oldest are dropped and counted (their numbers are skipped, so readers see the gap).
#[derive(Debug, Clone, Default)]
pub struct Outbox {
    replies: heapless::Vec<Reply, REPLIES_PER_CYCLE>,
    dropped: u64,
}

impl Outbox {
    /// Add a reply; drops the oldest when full.
    pub fn push(&mut self, reply: Reply) {
        if self.replies.is_full() {
            self.replies.remove(0);
            self.dropped += 1;
        }
        // Cannot fail: there is room now.
        let _ = self.replies.push(reply);
    }

    /// The replies kept, oldest first.
    pub fn replies(&self) -> &[Reply] {
        &self.replies
    }

    /// Replies given but dropped (more than one cycle may give).
    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    pub fn clear(&mut self) {
        self.replies.clear();
        self.dropped = 0;
    }
}

/// One axis in this cycle [rad, rad/s, rad/s^2, A].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AxisView {
    /// The reported joint position: the commanded one in PVT, the measured one otherwise.
    pub position: f64,
    pub velocity: f64,
    pub acceleration: f64,
    /// Measured current, or in the torque modes the current of the commanded torque.
    pub current: f64,
    pub measured_position: f64,
    pub commanded_position: f64,
    /// The position commanded two cycles ago less the measured one.
    pub following_error: f64,
    /// Motor heating, 0 (cold) to 1 (the limit).
    pub i2t: f64,
    pub online: bool,
    pub enabled: bool,
    pub fault: bool,
    pub calibrated: bool,
    /// The i2t protection reduces the current.
    pub derated: bool,
}

/// The controller after one step.
#[derive(Debug, Clone, Default)]
pub struct CycleView {
    /// Steps since start.
    pub cycle: u64,
    pub mode: Mode,
    pub axes: [AxisView; NUM_AXES],
    pub pvt_queued: u32,
    pub pvt_capacity: u32,
    pub estop: bool,
    pub all_calibrated: bool,
    pub pvt_starved: bool,
    /// The client that controls the arm's motion (0: nobody).
    pub owner_client_id: u64,
    /// `mcm-rt` was asked to stop: the controlled stop and disable run (or ran).
    pub shutting_down: bool,
    /// The replies given this cycle.
    pub replies: Outbox,
    /// The latest safety error reported (`None` since start); its `unix_ns` is 0: the composer
    /// stamps the wall clock of the cycle that reports it.
    pub last_error: Option<SafetyError>,
    /// The master's counters (bad frames, frames dropped, events dropped) and the bus errors
    /// that [`crate::cycle::Cycle`] counts, since start.
    pub bus: BusCounters,
    /// The active tool.
    pub tool: mcm_shared::tool::Tool,
}
