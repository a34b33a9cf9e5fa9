//! PVT streaming: staging of `pvt_points` batches, their validation, the queue, and the
//! reference that passes through every point at its time.
//!
//! Runs inside the cycle; all storage is preallocated (the queue holds
//! [`DEFAULT_PVT_CAPACITY`] points, the staging area one whole batch).
//!
//! Timing: a stream starts at the commanded state when its first batch is queued; the first
//! point is reached `dt` later, the next one `dt` after that, and so on. Between points the
//! reference is the cubic Hermite spline through (position, velocity). When the queue runs dry
//! on a point with zero velocity the stream ends there; with a non-zero velocity the axes stop
//! with a controlled stop at their maximum deceleration (not an error; `starved` is set).

use crate::params::JointParams;
use crate::trajectory::{
    DEFAULT_PVT_CAPACITY, JointSample, PvtPoint, PvtQueue, PvtSegment, SegmentError,
};
use mcm_shared::NUM_AXES;
use mcm_shared::command::Axis;
use mcm_shared::pvt::{PointLimits, check_point as check_point_limits};
use mcm_shared::reply::{PvtQuantity, Reason};
use mcm_shared::units::rad_to_deg;

/// Most points in one batch.
pub const MAX_BATCH: usize = 1000;
/// A point whose speed is below this counts as at rest [rad/s].
const REST_SPEED: f64 = 1e-6;

/// Why a batch was refused; nothing of it was queued.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BatchError {
    /// The batch does not fit: points offered, places free.
    QueueFull { offered: usize, free: usize },
    /// A point breaks a limit: point index (0-based), axis (0-based), which quantity, value
    /// and limit (SI units).
    Point {
        index: usize,
        axis: usize,
        what: PvtQuantity,
        value: f64,
        limit: f64,
    },
    /// More points than one batch may hold.
    TooLong { limit: usize },
}

impl BatchError {
    /// The refusal it stands for (figures in the user's degrees; a batch longer than one may
    /// be is a full queue: one point more offered than fits).
    pub fn reason(&self) -> Reason {
        match *self {
            BatchError::QueueFull { offered, free } => Reason::QueueFull {
                offered: u32::try_from(offered).unwrap_or(u32::MAX),
                free: u32::try_from(free).unwrap_or(u32::MAX),
            },
            BatchError::TooLong { limit } => {
                let limit = u32::try_from(limit).unwrap_or(u32::MAX - 1);
                Reason::QueueFull {
                    offered: limit + 1,
                    free: limit,
                }
            }
            BatchError::Point {
                index,
                axis,
                what,
                value,
                limit,
            } => Reason::PvtPoint {
                axis: Axis::ALL[axis],
                point: u32::try_from(index + 1).unwrap_or(u32::MAX),
                quantity: what,
                value: rad_to_deg(value),
                limit: rad_to_deg(limit),
            },
        }
    }
}

/// What the stream does this cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StreamState {
    /// No stream.
    Idle,
    /// Following the points.
    Running,
    /// Ran dry while moving: the caller must stop from this state.
    Starved(JointSample),
    /// Reached its last point at rest.
    Finished([f64; NUM_AXES]),
}

/// The PVT stream of the controller.
pub struct PvtStream {
    dt: f64,
    queue: PvtQueue<DEFAULT_PVT_CAPACITY>,
    staging: [PvtPoint; MAX_BATCH],
    staged: usize,
    staging_client: u64,
    /// The first error of the batch being staged: the whole batch will be refused.
    poisoned: Option<BatchError>,
    running: bool,
    /// The point the current segment starts from, and the time since it.
    from: PvtPoint,
    tau: f64,
}

impl Default for PvtStream {
    fn default() -> Self {
        Self::new()
    }
}

impl PvtStream {
    pub fn new() -> Self {
        Self {
            dt: 0.01,
            queue: PvtQueue::new(),
            staging: [PvtPoint::default(); MAX_BATCH],
            staged: 0,
            staging_client: 0,
            poisoned: None,
            running: false,
            from: PvtPoint::default(),
            tau: 0.0,
        }
    }

    /// Set the point spacing (on entering PVT) and forget everything queued.
    pub fn reset(&mut self, dt: f64) {
        self.dt = dt;
        self.queue.clear();
        self.staged = 0;
        self.running = false;
        self.tau = 0.0;
    }

    pub fn dt(&self) -> f64 {
        self.dt
    }

    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    pub fn capacity(&self) -> usize {
        self.queue.capacity()
    }

    pub fn running(&self) -> bool {
        self.running
    }

    /// Add points of a batch sent by `client`. A new client's points discard another client's
    /// unfinished batch. After an error, the rest of the batch is ignored and the batch will be
    /// refused whole by [`PvtStream::commit`].
    pub fn stage(&mut self, client: u64, points: &[PvtPoint]) -> Result<(), BatchError> {
        if client != self.staging_client {
            self.staged = 0;
            self.poisoned = None;
            self.staging_client = client;
        }
        if let Some(e) = self.poisoned {
            return Err(e);
        }
        if self.staged + points.len() > MAX_BATCH {
            self.staged = 0;
            let e = BatchError::TooLong { limit: MAX_BATCH };
            self.poisoned = Some(e);
            return Err(e);
        }
        self.staging[self.staged..self.staged + points.len()].copy_from_slice(points);
        self.staged += points.len();
        Ok(())
    }

    /// Validate the staged batch of `client` and queue it whole, or refuse it whole. `start`
    /// is the commanded state the stream starts from if it is not running.
    pub fn commit(
        &mut self,
        client: u64,
        start: &JointSample,
        p: &JointParams,
    ) -> Result<(), BatchError> {
        if client != self.staging_client {
            self.staged = 0;
            self.poisoned = None;
        }
        let n = self.staged;
        self.staged = 0;
        if let Some(e) = self.poisoned.take() {
            return Err(e);
        }
        if n > self.queue.free() {
            return Err(BatchError::QueueFull {
                offered: n,
                free: self.queue.free(),
            });
        }
        let mut prev = if self.running {
            self.queue.last().copied().unwrap_or(self.from)
        } else {
            PvtPoint {
                position: start.position,
                velocity: start.velocity,
            }
        };
        for (index, point) in self.staging[..n].iter().enumerate() {
            check_point(index, point, p)?;
            let seg = PvtSegment::new(&prev, point, self.dt);
            if let Err(e) = seg.check(&p.reach_min, &p.reach_max, &p.limits) {
                let (what, value, limit) = match e.error {
                    SegmentError::Position {
                        position, min, max, ..
                    } => (
                        PvtQuantity::Position,
                        position,
                        if position > max { max } else { min },
                    ),
                    SegmentError::Velocity {
                        velocity, limit, ..
                    } => (PvtQuantity::Velocity, velocity, limit),
                    SegmentError::Acceleration {
                        acceleration,
                        limit,
                        ..
                    } => (PvtQuantity::Acceleration, acceleration, limit),
                    _ => (PvtQuantity::Position, f64::NAN, f64::NAN),
                };
                return Err(BatchError::Point {
                    index,
                    axis: e.axis,
                    what,
                    value,
                    limit,
                });
            }
            prev = *point;
        }
        self.queue
            .push_batch(&self.staging[..n])
            .map_err(|e| BatchError::QueueFull {
                offered: e.offered,
                free: e.free,
            })?;
        if !self.running && n > 0 {
            self.running = true;
            self.from = PvtPoint {
                position: start.position,
                velocity: start.velocity,
            };
            self.tau = 0.0;
        }
        Ok(())
    }

    /// Advance by `period` and give the reference. Call only while in PVT mode.
    pub fn advance(&mut self, period: f64) -> (StreamState, JointSample) {
        if !self.running {
            return (StreamState::Idle, JointSample::default());
        }
        self.tau += period;
        while self.tau >= self.dt {
            match self.queue.pop() {
                Some(next) => {
                    self.from = next;
                    self.tau -= self.dt;
                }
                None => break,
            }
        }
        match self.queue.peek() {
            Some(next) => {
                let s = PvtSegment::new(&self.from, next, self.dt).sample(self.tau.min(self.dt));
                (StreamState::Running, s)
            }
            None => {
                self.running = false;
                let at = JointSample {
                    position: self.from.position,
                    velocity: self.from.velocity,
                    acceleration: [0.0; NUM_AXES],
                };
                if self.from.velocity.iter().all(|v| v.abs() < REST_SPEED) {
                    (StreamState::Finished(self.from.position), at)
                } else {
                    (StreamState::Starved(at), at)
                }
            }
        }
    }
}

/// The per-point checks shared with the gateway ([`mcm_shared::pvt::check_point`]).
fn check_point(index: usize, pt: &PvtPoint, p: &JointParams) -> Result<(), BatchError> {
    let limits = PointLimits {
        reach_min: p.reach_min,
        reach_max: p.reach_max,
        velocity: core::array::from_fn(|i| p.limits[i].velocity),
    };
    check_point_limits(&pt.position, &pt.velocity, &limits).map_err(|e| BatchError::Point {
        index,
        axis: e.axis,
        what: e.what,
        value: e.value,
        limit: e.limit,
    })
}

#[cfg(test)]
mod tests;
